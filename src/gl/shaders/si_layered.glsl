// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Layered animation's functions of the public include, which si_skinning.glsl includes with
// SI_LAYERS (after its records, layer records and mask table): the overlay composed on its mask
// (siLayeredJointRows, siSkinLayered, siSkinPreviousLayered; si::emulateLayeredMatrix), the
// local-space blend between weights (siLocalBlend; si::localBlend) and a 2D blend's chain of
// layers (siLayeredChainRows; si::emulateLayeredChain).
#ifndef SI_LAYERED_GLSL
#define SI_LAYERED_GLSL
// The affine inverse of rows (r0, r1, r2): the 3x3's inverse and -inverse * translation.
void siAffineInverse(vec4 r0, vec4 r1, vec4 r2, out vec4 i0, out vec4 i1, out vec4 i2) {
  mat3 inv = inverse(mat3(r0.xyz, r1.xyz, r2.xyz));  // Columns of the transpose: rows of A^-1.
  vec3 t = vec3(r0.w, r1.w, r2.w);
  i0 = vec4(inv[0], -dot(inv[0], t));
  i1 = vec4(inv[1], -dot(inv[1], t));
  i2 = vec4(inv[2], -dot(inv[2], t));
}
// Row k of (A * B) for affine rows.
vec4 siMulRow(vec4 a, vec4 b0, vec4 b1, vec4 b2) {
  return a.x * b0 + a.y * b1 + a.z * b2 + vec4(0.0, 0.0, 0.0, a.w);
}
// Rows C = A * B for affine rows (C may be A or B: GLSL copies arguments in and out).
void siMulRows(vec4 a0, vec4 a1, vec4 a2, vec4 b0, vec4 b1, vec4 b2, out vec4 c0, out vec4 c1,
               out vec4 c2) {
  c0 = siMulRow(a0, b0, b1, b2);
  c1 = siMulRow(a1, b0, b1, b2);
  c2 = siMulRow(a2, b0, b1, b2);
}

// Quaternions are (x, y, z, w).
// The unit quaternion of the rotation in rows (r0, r1, r2) (Shepperd's method).
vec4 siQuatFromRows(vec3 r0, vec3 r1, vec3 r2) {
  float tr = r0.x + r1.y + r2.z;
  vec4 q;
  if (tr > 0.0) {
    float s = sqrt(tr + 1.0) * 2.0;
    q = vec4((r2.y - r1.z) / s, (r0.z - r2.x) / s, (r1.x - r0.y) / s, 0.25 * s);
  } else if (r0.x > r1.y && r0.x > r2.z) {
    float s = sqrt(1.0 + r0.x - r1.y - r2.z) * 2.0;
    q = vec4(0.25 * s, (r0.y + r1.x) / s, (r0.z + r2.x) / s, (r2.y - r1.z) / s);
  } else if (r1.y > r2.z) {
    float s = sqrt(1.0 + r1.y - r0.x - r2.z) * 2.0;
    q = vec4((r0.y + r1.x) / s, 0.25 * s, (r1.z + r2.y) / s, (r0.z - r2.x) / s);
  } else {
    float s = sqrt(1.0 + r2.z - r0.x - r1.y) * 2.0;
    q = vec4((r0.z + r2.x) / s, (r1.z + r2.y) / s, 0.25 * s, (r1.x - r0.y) / s);
  }
  return normalize(q);
}
// si::localBlend: the joint transform a fraction t of the way from rows A to rows C (each the
// joint relative to its parent): the rotation slerped the shorter way, the uniform scale
// lerped, what the linear parts hold beyond them lerped, and the bind-pose origin `pivot`
// taken where the two take it, lerped. Mirrored or degenerate: the element-wise lerp.
void siLocalBlend(vec4 a0, vec4 a1, vec4 a2, vec4 c0, vec4 c1, vec4 c2, vec3 pivot, float t,
                  out vec4 r0, out vec4 r1, out vec4 r2) {
  r0 = mix(a0, c0, t);
  r1 = mix(a1, c1, t);
  r2 = mix(a2, c2, t);
  float det_a = determinant(mat3(a0.xyz, a1.xyz, a2.xyz));
  float det_c = determinant(mat3(c0.xyz, c1.xyz, c2.xyz));
  if (!(det_a > 1e-30 && det_c > 1e-30)) return;
  float sa = pow(det_a, 1.0 / 3.0), sc = pow(det_c, 1.0 / 3.0);
  vec4 qa = siQuatFromRows(a0.xyz / sa, a1.xyz / sa, a2.xyz / sa);
  vec4 qc = siQuatFromRows(c0.xyz / sc, c1.xyz / sc, c2.xyz / sc);
  float d = dot(qa, qc);
  if (d < 0.0) {  // The shorter arc, as the reference's slerp takes it.
    qc = -qc;
    d = -d;
  }
  float angle = acos(min(d, 1.0));
  vec4 q = mix(qa, qc, t);
  if (angle > 1e-4) q = (sin((1.0 - t) * angle) * qa + sin(t * angle) * qc) / sin(angle);
  vec4 g0, g1, g2, ga0, ga1, ga2, gc0, gc1, gc2;
  siRigidRows(normalize(q), vec4(0.0, 0.0, 0.0, mix(sa, sc, t)), g0, g1, g2);
  siRigidRows(qa, vec4(0.0, 0.0, 0.0, sa), ga0, ga1, ga2);
  siRigidRows(qc, vec4(0.0, 0.0, 0.0, sc), gc0, gc1, gc2);
  vec3 l0 = g0.xyz + mix(a0.xyz - ga0.xyz, c0.xyz - gc0.xyz, t);
  vec3 l1 = g1.xyz + mix(a1.xyz - ga1.xyz, c1.xyz - gc1.xyz, t);
  vec3 l2 = g2.xyz + mix(a2.xyz - ga2.xyz, c2.xyz - gc2.xyz, t);
  vec4 p = vec4(pivot, 1.0);
  vec3 origin = mix(vec3(dot(a0, p), dot(a1, p), dot(a2, p)), vec3(dot(c0, p), dot(c1, p), dot(c2, p)), t);
  r0 = vec4(l0, origin.x - dot(l0, pivot));
  r1 = vec4(l1, origin.y - dot(l1, pivot));
  r2 = vec4(l2, origin.z - dot(l2, pivot));
}

// The base rows (b) and the overlay rows (v) of palette slot `slot`; the identity for -1 (the
// model anchor).
void siLinkRows(SiInstance inst, uvec4 layer, int slot, out vec4 b0, out vec4 b1, out vec4 b2,
                out vec4 v0, out vec4 v1, out vec4 v2) {
  b0 = vec4(1.0, 0.0, 0.0, 0.0);
  b1 = vec4(0.0, 1.0, 0.0, 0.0);
  b2 = vec4(0.0, 0.0, 1.0, 0.0);
  v0 = b0;
  v1 = b1;
  v2 = b2;
  if (slot < 0) return;
  siInstanceJointRows(inst, uint(slot), b0, b1, b2);
  siInterpolatedRows(layer.x, layer.y, layer.z, uint(slot), v0, v1, v2);
}
// Rows C replaced by inverse(P) * C.
void siRelativeRows(vec4 p0, vec4 p1, vec4 p2, inout vec4 c0, inout vec4 c1, inout vec4 c2) {
  vec4 i0, i1, i2;
  siAffineInverse(p0, p1, p2, i0, i1, i2);
  siMulRows(i0, i1, i2, c0, c1, c2, c0, c1, c2);
}
// One link up a chain walk: the rows composed so far, x, placed under the link's rows l
// (x = l * x), and the walk's lower rows r moved to the link's upper end p.
void siChainClimb(vec4 l0, vec4 l1, vec4 l2, vec4 p0, vec4 p1, vec4 p2, inout vec4 x0,
                  inout vec4 x1, inout vec4 x2, out vec4 r0, out vec4 r1, out vec4 r2) {
  siMulRows(l0, l1, l2, x0, x1, x2, x0, x1, x2);
  r0 = p0;
  r1 = p1;
  r2 = p2;
}
// The bind origin of masked slot `link` in the mask table from `table` (the pivot its local
// blend turns about).
vec3 siLinkPivot(uint table, uint slots, uint link) {
  uint at = table + 2u * slots + 3u * link;
  return intBitsToFloat(ivec3(si_mask_anchor[at], si_mask_anchor[at + 1u], si_mask_anchor[at + 2u]));
}

// The mask table's entries of mask `mask` (si::layerMaskTable: [0] the palette slots, [1] the
// morph words per mask, then per mask its anchors, parents, bind origins and morph bits).
uint siMaskTable(uint mask) {
  uint slots = uint(si_mask_anchor[0]);
  return 2u + mask * (5u * slots + uint(si_mask_anchor[1]));
}

// A layer record's mask index (bit 31 of its last word flags a 2D blend's extra layers).
uint siLayerMask(uvec4 layer) { return (layer.w >> 16) & 0x7FFFu; }
float siLayerWeight(uvec4 layer) { return float(layer.w & 0xFFFFu) / 65535.0; }

// The rows of palette slot `joint` with the layer record `layer` composed on it:
// si::emulateLayeredMatrix. Outside the layer's mask, or at weight 0, the base rows.
void siLayeredJointRows(SiInstance inst, uvec4 layer, uint joint, out vec4 r0, out vec4 r1,
                        out vec4 r2) {
  siInstanceJointRows(inst, joint, r0, r1, r2);
  float w = float(layer.w & 0xFFFFu) / 65535.0;
  if (w == 0.0) return;
  uint slots = uint(si_mask_anchor[0]);
  uint table = siMaskTable(siLayerMask(layer));
  int anchor = si_mask_anchor[table + joint];
  if (anchor == -2) return;
  vec4 o0, o1, o2, p0, p1, p2, q0, q1, q2;
  siInterpolatedRows(layer.x, layer.y, layer.z, joint, o0, o1, o2);
  if (w >= 1.0) {  // Base anchor * inverse(overlay anchor) * overlay.
    siLinkRows(inst, layer, anchor, p0, p1, p2, q0, q1, q2);
    siRelativeRows(q0, q1, q2, o0, o1, o2);
    siMulRows(p0, p1, p2, o0, o1, o2, r0, r1, r2);
    return;
  }
  // Between: each link from the joint up to the anchor (its masked parent slots) blended in
  // local space, composed as x = link * x, then placed on the base's anchor. r and o hold the
  // link's lower end (base and overlay), p and q its upper end.
  vec4 x0 = vec4(1.0, 0.0, 0.0, 0.0), x1 = vec4(0.0, 1.0, 0.0, 0.0), x2 = vec4(0.0, 0.0, 1.0, 0.0);
  uint link = joint;
  for (uint steps = 0u; steps <= slots; ++steps) {
    int parent = steps < slots ? si_mask_anchor[table + slots + link] : -1;
    siLinkRows(inst, layer, parent >= 0 ? parent : anchor, p0, p1, p2, q0, q1, q2);
    siRelativeRows(p0, p1, p2, r0, r1, r2);
    siRelativeRows(q0, q1, q2, o0, o1, o2);
    vec4 l0, l1, l2;
    siLocalBlend(r0, r1, r2, o0, o1, o2, siLinkPivot(table, slots, link), w, l0, l1, l2);
    siChainClimb(l0, l1, l2, p0, p1, p2, x0, x1, x2, r0, r1, r2);
    o0 = q0;
    o1 = q1;
    o2 = q2;
    if (parent < 0) break;
    link = uint(parent);
  }
  // The chain's last link hangs from the anchor, whose base rows r now holds.
  siMulRows(r0, r1, r2, x0, x1, x2, r0, r1, r2);
}

// Layer record `layer`'s rows of palette slot `slot`; the identity for -1 (the model anchor).
void siLayerSlotRows(uvec4 layer, int slot, out vec4 r0, out vec4 r1, out vec4 r2) {
  r0 = vec4(1.0, 0.0, 0.0, 0.0);
  r1 = vec4(0.0, 1.0, 0.0, 0.0);
  r2 = vec4(0.0, 0.0, 1.0, 0.0);
  if (slot >= 0) siInterpolatedRows(layer.x, layer.y, layer.z, uint(slot), r0, r1, r2);
}
// Base rows of palette slot `slot`; the identity for -1.
void siBaseSlotRows(SiInstance inst, int slot, out vec4 r0, out vec4 r1, out vec4 r2) {
  r0 = vec4(1.0, 0.0, 0.0, 0.0);
  r1 = vec4(0.0, 1.0, 0.0, 0.0);
  r2 = vec4(0.0, 0.0, 1.0, 0.0);
  if (slot >= 0) siInstanceJointRows(inst, uint(slot), r0, r1, r2);
}

// The rows of palette slot `joint` with the overlay `layer` and then a 2D blend's extra layer
// records `e1`, `e2` composed on the overlay's mask, each blended in local space on what those
// before it gave: si::emulateLayeredChain. Without kLayerExtrasBit, siLayeredJointRows.
void siLayeredChainRows(SiInstance inst, uvec4 layer, uvec4 e1, uvec4 e2, uint joint,
                        out vec4 r0, out vec4 r1, out vec4 r2) {
  if ((layer.w & 0x80000000u) == 0u) {
    siLayeredJointRows(inst, layer, joint, r0, r1, r2);
    return;
  }
  siInstanceJointRows(inst, joint, r0, r1, r2);
  uint slots = uint(si_mask_anchor[0]);
  uint table = siMaskTable(siLayerMask(layer));
  int anchor = si_mask_anchor[table + joint];
  if (anchor == -2) return;
  uvec4 l[3] = uvec4[3](layer, e1, e2);
  float w[3] = float[3](siLayerWeight(layer), siLayerWeight(e1), siLayerWeight(e2));
  // From the last layer at weight 1 (it replaces those before it) on.
  int first = 0, drawn = 0, last = 0;
  for (int k = 0; k < 3; ++k)
    if (w[k] >= 1.0) first = k;
  for (int k = first; k < 3; ++k)
    if (w[k] > 0.0) {
      ++drawn;
      last = k;
    }
  if (drawn == 0) return;
  vec4 a0, a1, a2, o0, o1, o2;
  siBaseSlotRows(inst, anchor, a0, a1, a2);
  if (drawn == 1 && w[last] >= 1.0) {  // Base anchor * inverse(layer anchor) * layer.
    vec4 q0, q1, q2;
    siLayerSlotRows(l[last], anchor, q0, q1, q2);
    siLayerSlotRows(l[last], int(joint), o0, o1, o2);
    siRelativeRows(q0, q1, q2, o0, o1, o2);
    siMulRows(a0, a1, a2, o0, o1, o2, r0, r1, r2);
    return;
  }
  bool from_layer = w[first] >= 1.0;
  // Each layer's rows of the link's lower end (c), the base's in r.
  vec4 c[9];
  for (int k = first; k < 3; ++k)
    if (w[k] > 0.0) siLayerSlotRows(l[k], int(joint), c[3 * k], c[3 * k + 1], c[3 * k + 2]);
  vec4 x0 = vec4(1.0, 0.0, 0.0, 0.0), x1 = vec4(0.0, 1.0, 0.0, 0.0), x2 = vec4(0.0, 0.0, 1.0, 0.0);
  uint link = joint;
  for (uint steps = 0u; steps <= slots; ++steps) {
    int parent = steps < slots ? si_mask_anchor[table + slots + link] : -1;
    int up = parent >= 0 ? parent : anchor;
    vec4 p0, p1, p2;
    siBaseSlotRows(inst, up, p0, p1, p2);
    siRelativeRows(p0, p1, p2, r0, r1, r2);
    vec3 pivot = siLinkPivot(table, slots, link);
    for (int k = first; k < 3; ++k) {
      if (!(w[k] > 0.0)) continue;
      vec4 q0, q1, q2;
      siLayerSlotRows(l[k], up, q0, q1, q2);
      o0 = c[3 * k];
      o1 = c[3 * k + 1];
      o2 = c[3 * k + 2];
      siRelativeRows(q0, q1, q2, o0, o1, o2);
      if (k == first && from_layer) {
        r0 = o0;
        r1 = o1;
        r2 = o2;
      } else {
        vec4 b0 = r0, b1 = r1, b2 = r2;
        siLocalBlend(b0, b1, b2, o0, o1, o2, pivot, w[k], r0, r1, r2);
      }
      c[3 * k] = q0;
      c[3 * k + 1] = q1;
      c[3 * k + 2] = q2;
    }
    siChainClimb(r0, r1, r2, p0, p1, p2, x0, x1, x2, r0, r1, r2);
    if (parent < 0) break;
    link = uint(parent);
  }
  // The chain's last link hangs from the anchor, whose base rows r now holds.
  siMulRows(r0, r1, r2, x0, x1, x2, r0, r1, r2);
}

// siSkin with the instance's overlay (its layer record) on its mask.
void siSkinLayered(SiInstance inst, uvec4 layer, uvec4 joints, vec4 weights, out vec4 m0,
                   out vec4 m1, out vec4 m2) {
  SI_SKIN_SUM(joints, weights, siLayeredJointRows(inst, layer, joint, r0, r1, r2))
}
#ifdef SI_PREVIOUS_RECORDS
// siSkinPrevious with the slot's previous layer record (InstanceBatcher::buildPreviousLayers):
// where the vertex was drawn in the previous frame, its overlay included.
vec3 siSkinPreviousLayered(uint instance, uvec4 joints, vec4 weights, vec3 position) {
  SiInstance prev = si_previous_instances[instance];
  vec4 m0, m1, m2;
  siSkinLayered(prev, si_previous_layers[instance], joints, weights, m0, m1, m2);
  return siPlacePoint(prev, m0, m1, m2, position);
}
#endif
#endif
