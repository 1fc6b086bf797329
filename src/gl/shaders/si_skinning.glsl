// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The skinning include for your own vertex (or compute) shaders: the instance record, the
// instance block, the palette and functions that fetch, interpolate, crossfade and blend the
// bone matrices exactly as si::emulateSkinningMatrix() and si::emulateSkinning() do on the CPU.
// Interface version 7 (2: the fraction words carry the interval mode, cubic clips; 3: the
// record's fourth blend word is the appearance: tint RGB8 and the custom texture layer; 4: the
// previous frame's records and siSkinPrevious, for motion vectors; 5: layered animation, the
// layer records, the mask table and siSkinLayered; 6: the mask table holds each slot's bind-pose
// origin and weights between 0 and 1 blend each joint in local space; 7: every binding is a
// define, si_palette_info is in a uniform block, descriptor sets under Vulkan; 8: GLSL ES 3.00
// (OpenGL ES 3.0, WebGL 2) through si_profile.glsl: there the application binds the blocks and
// the palette sampler after linking);
// docs/glsl-interface.md documents every name, binding and define.
//
// Before including, define SI_MAX_INSTANCES (records per draw: InstanceBatcher::
// capacityPerDraw()), or define SI_INSTANCES_IN_STORAGE to read the records from a shader
// storage buffer instead of the uniform block.
// Bindings, each a define you may set before including (default in brackets):
//   SI_RECORDS_BINDING [0]       the records (uniform, or storage with SI_INSTANCES_IN_STORAGE)
//   SI_PALETTE_BINDING [0]       the palette texture (the texture unit under OpenGL)
//   SI_PALETTE_INFO_BINDING [4]  uniform block SiPaletteInfo { uvec4 si_palette_info; }
//                                (si::paletteShaderInfo())
//   SI_PREVIOUS_BINDING [1], SI_LAYER_BINDING [2], SI_PREVIOUS_LAYER_BINDING [3],
//   SI_MASK_BINDING [8]          motion vectors and layered animation, below
// Under Vulkan (glslang defines VULKAN), every resource is in descriptor set SI_DESCRIPTOR_SET
// [0]; Vulkan shares binding numbers between resource kinds, so give each its own there. Under
// GLSL ES 3.00 the bindings are the application's to set (si_profile.glsl): uniform blocks
// SiInstances, SiPaletteInfo (and SiPreviousInstances) with glUniformBlockBinding, the sampler
// si_palette with glUniform1i; storage-buffer variants need GLSL ES 3.10.
// Motion vectors: define SI_PREVIOUS_RECORDS for the previous frame's records, in the same
// slots, at (uniform or storage) buffer binding SI_PREVIOUS_BINDING (written by
// si::InstanceBatcher::buildPrevious) and siSkinPrevious(); SI_PREVIOUS_IN_STORAGE reads them
// (and the previous layer records) from a storage buffer when the records are in a uniform block.
// Layered animation: define SI_LAYERS for each slot's layer record (si::LayerRecord, a uvec4)
// at (uniform or storage: SI_INSTANCES_IN_STORAGE or SI_LAYERS_IN_STORAGE) buffer binding
// SI_LAYER_BINDING (written by si::InstanceBatcher::buildLayers), the crowd's mask table at
// storage binding SI_MASK_BINDING (si::layerMaskTable) and siSkinLayered(); with
// SI_PREVIOUS_RECORDS too, the previous layer records at binding SI_PREVIOUS_LAYER_BINDING
// (InstanceBatcher::buildPreviousLayers) and siSkinPreviousLayered().
#ifndef SI_SKINNING_GLSL
#define SI_SKINNING_GLSL
#define SI_GLSL_INTERFACE_VERSION 8
#include "si_profile.glsl"
#include "si_instance_record.glsl"
#include "si_transform.glsl"

#ifndef SI_RECORDS_BINDING
#define SI_RECORDS_BINDING 0
#endif
#ifndef SI_PALETTE_BINDING
#define SI_PALETTE_BINDING 0
#endif
#ifndef SI_PALETTE_INFO_BINDING
#define SI_PALETTE_INFO_BINDING 4
#endif
#ifndef SI_PREVIOUS_BINDING
#define SI_PREVIOUS_BINDING 1
#endif
#ifndef SI_LAYER_BINDING
#define SI_LAYER_BINDING 2
#endif
#ifndef SI_PREVIOUS_LAYER_BINDING
#define SI_PREVIOUS_LAYER_BINDING 3
#endif
#ifndef SI_MASK_BINDING
#define SI_MASK_BINDING 8
#endif
#ifdef SI_INSTANCES_IN_STORAGE
layout(std430 SI_WITH_BINDING(SI_RECORDS_BINDING)) readonly buffer SiInstances {
  SiInstance si_instances[];
};
#else
layout(std140 SI_WITH_BINDING(SI_RECORDS_BINDING)) uniform SiInstances {
  SiInstance si_instances[SI_MAX_INSTANCES];
};
#endif
#ifdef SI_PREVIOUS_RECORDS
#if defined(SI_INSTANCES_IN_STORAGE) || defined(SI_PREVIOUS_IN_STORAGE)
layout(std430 SI_WITH_BINDING(SI_PREVIOUS_BINDING)) readonly buffer SiPreviousInstances {
  SiInstance si_previous_instances[];
};
#else
layout(std140 SI_WITH_BINDING(SI_PREVIOUS_BINDING)) uniform SiPreviousInstances {
  SiInstance si_previous_instances[SI_MAX_INSTANCES];
};
#endif
#endif
#ifdef SI_LAYERS
#if defined(SI_INSTANCES_IN_STORAGE) || defined(SI_LAYERS_IN_STORAGE)
layout(std430 SI_WITH_BINDING(SI_LAYER_BINDING)) readonly buffer SiLayers { uvec4 si_layers[]; };
#else
layout(std140 SI_WITH_BINDING(SI_LAYER_BINDING)) uniform SiLayers {
  uvec4 si_layers[SI_MAX_INSTANCES];
};
#endif
#ifdef SI_PREVIOUS_RECORDS
#if defined(SI_INSTANCES_IN_STORAGE) || defined(SI_LAYERS_IN_STORAGE) || \
    defined(SI_PREVIOUS_IN_STORAGE)
layout(std430 SI_WITH_BINDING(SI_PREVIOUS_LAYER_BINDING)) readonly buffer SiPreviousLayers {
  uvec4 si_previous_layers[];
};
#else
layout(std140 SI_WITH_BINDING(SI_PREVIOUS_LAYER_BINDING)) uniform SiPreviousLayers {
  uvec4 si_previous_layers[SI_MAX_INSTANCES];
};
#endif
#endif
// [0]: palette slots per mask; then per mask, per slot: -2 outside the mask, -1 the overlay's
// own matrix, else the anchor slot.
layout(std430 SI_WITH_BINDING(SI_MASK_BINDING)) readonly buffer SiLayerMasks {
  int si_mask_anchor[];
};
#endif
SI_BINDING_LAYOUT(SI_PALETTE_BINDING) uniform sampler2D si_palette;
// x: log2 of the palette's width, y: joint stride in texels, z: 0 matrices, 1 quaternions.
layout(std140 SI_WITH_BINDING(SI_PALETTE_INFO_BINDING)) uniform SiPaletteInfo {
  uvec4 si_palette_info;
};

ivec2 siTexel(uint i) {
  return ivec2(int(i & ((1u << si_palette_info.x) - 1u)), int(i >> si_palette_info.x));
}
vec4 siFetch(uint i) { return texelFetch(si_palette, siTexel(i), 0); }

// Rows of a rigid joint (unit quaternion q, translation and uniform scale ts).
void siRigidRows(vec4 q, vec4 ts, out vec4 r0, out vec4 r1, out vec4 r2) {
  float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  r0 = vec4(vec3(1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy)) * ts.w, ts.x);
  r1 = vec4(vec3(2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx)) * ts.w, ts.y);
  r2 = vec4(vec3(2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy)) * ts.w, ts.z);
}

// Catmull-Rom weights of frames i - 1, i, i + 1, i + 2 at fraction u for interval mode `mode`
// (1 cubic; 2: frame i starts the piece, frame i - 1 replaced by 3 f(i) - 3 f(i + 1) + f(i + 2);
// 3: frame i + 1 ends it, frame i + 2 replaced by 3 f(i + 1) - 3 f(i) + f(i - 1)).
vec4 siCubicWeights(float u, uint mode) {
  float u2 = u * u, u3 = u2 * u;
  vec4 w = vec4(0.5 * (-u3 + 2.0 * u2 - u), 0.5 * (3.0 * u3 - 5.0 * u2 + 2.0),
                0.5 * (-3.0 * u3 + 4.0 * u2 + u), 0.5 * (u3 - u2));
  if (mode == 2u) w = vec4(0.0, w.y + 3.0 * w.x, w.z - 3.0 * w.x, w.w + w.x);
  if (mode == 3u) w = vec4(w.x + w.w, w.y - 3.0 * w.w, w.z + 3.0 * w.w, 0.0);
  return w;
}

// Rows of the skinning matrix of palette slot `joint` between the frames starting at texels
// `frame` and `next`. `fraction` is the record's word: the float fraction with the interval
// mode in bits 30-31 (0 linear: two frames; 1-3 cubic: the frames one frame before and after
// too, which border frames always provide).
void siInterpolatedRows(uint frame, uint next, uint fraction, uint joint,
                        out vec4 r0, out vec4 r1, out vec4 r2) {
  float t = uintBitsToFloat(fraction & 0x3FFFFFFFu);
  uint mode = fraction >> 30;
  uint a = frame + joint * si_palette_info.y;
  uint b = next + joint * si_palette_info.y;
  if (mode != 0u) {
    uint f[4] = uint[4](a - (next - frame), a, b, b + (next - frame));
    vec4 w = siCubicWeights(t, mode);
    if (si_palette_info.z == 0u) {
      r0 = vec4(0.0);
      r1 = vec4(0.0);
      r2 = vec4(0.0);
      for (int k = 0; k < 4; ++k) {
        if ((k == 0 && mode == 2u) || (k == 3 && mode == 3u)) continue;  // Weight 0.
        r0 += w[k] * siFetch(f[k]);
        r1 += w[k] * siFetch(f[k] + 1u);
        r2 += w[k] * siFetch(f[k] + 2u);
      }
    } else {
      vec4 q1 = siFetch(a), q = vec4(0.0), ts = vec4(0.0);
      for (int k = 0; k < 4; ++k) {
        if ((k == 0 && mode == 2u) || (k == 3 && mode == 3u)) continue;
        vec4 qk = k == 1 ? q1 : siFetch(f[k]);
        q += w[k] * (dot(qk, q1) < 0.0 ? -qk : qk);  // Frame i's hemisphere.
        ts += w[k] * siFetch(f[k] + 1u);
      }
      siRigidRows(normalize(q), ts, r0, r1, r2);
    }
    return;
  }
  if (si_palette_info.z == 0u) {
    r0 = mix(siFetch(a), siFetch(b), t);
    r1 = mix(siFetch(a + 1u), siFetch(b + 1u), t);
    r2 = mix(siFetch(a + 2u), siFetch(b + 2u), t);
  } else {
    vec4 qa = siFetch(a), qb = siFetch(b);
    if (dot(qa, qb) < 0.0) qb = -qb;  // Shorter arc.
    siRigidRows(normalize(mix(qa, qb, t)), mix(siFetch(a + 1u), siFetch(b + 1u), t), r0, r1, r2);
  }
}

// The instance's skinning matrix rows for palette slot `joint`: clip A, crossfaded towards
// clip B by the record's weight (B's fetches are skipped when the weight is 0).
void siInstanceJointRows(SiInstance inst, uint joint, out vec4 r0, out vec4 r1, out vec4 r2) {
  siInterpolatedRows(inst.frames.x, inst.frames.y, inst.blend.x, joint, r0, r1, r2);
  float wb = uintBitsToFloat(inst.blend.z);
  if (wb > 0.0) {
    vec4 b0, b1, b2;
    siInterpolatedRows(inst.frames.z, inst.frames.w, inst.blend.y, joint, b0, b1, b2);
    r0 = mix(r0, b0, wb);
    r1 = mix(r1, b1, wb);
    r2 = mix(r2, b2, wb);
  }
}

// Blends the matrices of up to 4 influences by weight, branching past zero weights.
void siSkin(SiInstance inst, uvec4 joints, vec4 weights, out vec4 m0, out vec4 m1, out vec4 m2) {
  m0 = vec4(0.0);
  m1 = vec4(0.0);
  m2 = vec4(0.0);
  for (int k = 0; k < 4; ++k) {
    float w = weights[k];
    if (w == 0.0) continue;
    vec4 r0, r1, r2;
    siInstanceJointRows(inst, joints[k], r0, r1, r2);
    m0 += w * r0;
    m1 += w * r1;
    m2 += w * r2;
  }
}

#ifdef SI_PREVIOUS_RECORDS
// Where bind-pose `position` of instance slot `instance` was drawn in the previous frame:
// camera-relative (to the previous camera) world position, skinned with the instance's previous
// record exactly as siSkin skinned it then. Project it with the previous frame's camera.
vec3 siSkinPrevious(uint instance, uvec4 joints, vec4 weights, vec3 position) {
  SiInstance prev = si_previous_instances[instance];
  vec4 m0, m1, m2;
  siSkin(prev, joints, weights, m0, m1, m2);
  return siTransformPoint(prev.world_rows[0], prev.world_rows[1], prev.world_rows[2],
                          siTransformPoint(m0, m1, m2, position));
}
#endif

#ifdef SI_LAYERS
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
  vec4 d0 = siMulRow(i0, c0, c1, c2), d1 = siMulRow(i1, c0, c1, c2);
  c2 = siMulRow(i2, c0, c1, c2);
  c0 = d0;
  c1 = d1;
}

// The rows of palette slot `joint` with the layer record `layer` composed on it:
// si::emulateLayeredMatrix. Outside the layer's mask, or at weight 0, the base rows.
void siLayeredJointRows(SiInstance inst, uvec4 layer, uint joint, out vec4 r0, out vec4 r1,
                        out vec4 r2) {
  siInstanceJointRows(inst, joint, r0, r1, r2);
  float w = float(layer.w & 0xFFFFu) / 65535.0;
  if (w == 0.0) return;
  // The table: the slot count, then per mask its anchors, parents and bind origins (x, y, z).
  uint slots = uint(si_mask_anchor[0]);
  uint table = 1u + (layer.w >> 16) * 5u * slots;
  int anchor = si_mask_anchor[table + joint];
  if (anchor == -2) return;
  vec4 o0, o1, o2, p0, p1, p2, q0, q1, q2;
  siInterpolatedRows(layer.x, layer.y, layer.z, joint, o0, o1, o2);
  if (w >= 1.0) {  // Base anchor * inverse(overlay anchor) * overlay.
    siLinkRows(inst, layer, anchor, p0, p1, p2, q0, q1, q2);
    siRelativeRows(q0, q1, q2, o0, o1, o2);
    r0 = siMulRow(p0, o0, o1, o2);
    r1 = siMulRow(p1, o0, o1, o2);
    r2 = siMulRow(p2, o0, o1, o2);
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
    uint at = table + 2u * slots + 3u * link;
    vec3 pivot = intBitsToFloat(ivec3(si_mask_anchor[at], si_mask_anchor[at + 1u], si_mask_anchor[at + 2u]));
    vec4 l0, l1, l2;
    siLocalBlend(r0, r1, r2, o0, o1, o2, pivot, w, l0, l1, l2);
    vec4 n0 = siMulRow(l0, x0, x1, x2), n1 = siMulRow(l1, x0, x1, x2);
    x2 = siMulRow(l2, x0, x1, x2);
    x0 = n0;
    x1 = n1;
    r0 = p0;
    r1 = p1;
    r2 = p2;
    o0 = q0;
    o1 = q1;
    o2 = q2;
    if (parent < 0) break;
    link = uint(parent);
  }
  // The chain's last link hangs from the anchor, whose base rows r now holds.
  vec4 a0 = r0, a1 = r1, a2 = r2;
  r0 = siMulRow(a0, x0, x1, x2);
  r1 = siMulRow(a1, x0, x1, x2);
  r2 = siMulRow(a2, x0, x1, x2);
}

// siSkin with the instance's overlay (its layer record) on its mask.
void siSkinLayered(SiInstance inst, uvec4 layer, uvec4 joints, vec4 weights, out vec4 m0,
                   out vec4 m1, out vec4 m2) {
  m0 = vec4(0.0);
  m1 = vec4(0.0);
  m2 = vec4(0.0);
  for (int k = 0; k < 4; ++k) {
    float w = weights[k];
    if (w == 0.0) continue;
    vec4 r0, r1, r2;
    siLayeredJointRows(inst, layer, joints[k], r0, r1, r2);
    m0 += w * r0;
    m1 += w * r1;
    m2 += w * r2;
  }
}
#ifdef SI_PREVIOUS_RECORDS
// siSkinPrevious with the slot's previous layer record (InstanceBatcher::buildPreviousLayers):
// where the vertex was drawn in the previous frame, its overlay included.
vec3 siSkinPreviousLayered(uint instance, uvec4 joints, vec4 weights, vec3 position) {
  SiInstance prev = si_previous_instances[instance];
  vec4 m0, m1, m2;
  siSkinLayered(prev, si_previous_layers[instance], joints, weights, m0, m1, m2);
  return siTransformPoint(prev.world_rows[0], prev.world_rows[1], prev.world_rows[2],
                          siTransformPoint(m0, m1, m2, position));
}
#endif
#endif
#endif
