// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The skinning include for your own vertex (or compute) shaders: the instance record, the
// instance block, the palette and functions that fetch, interpolate, crossfade and blend the
// bone matrices exactly as si::emulateSkinningMatrix() and si::emulateSkinning() do on the CPU.
// Interface version 5 (2: the fraction words carry the interval mode, cubic clips; 3: the
// record's fourth blend word is the appearance: tint RGB8 and the custom texture layer; 4: the
// previous frame's records and siSkinPrevious, for motion vectors; 5: layered animation, the
// layer records, the mask table and siSkinLayered);
// docs/glsl-interface.md documents every name, binding and define.
//
// Before including, define SI_MAX_INSTANCES (records per draw: InstanceBatcher::
// capacityPerDraw()), or define SI_INSTANCES_IN_STORAGE to read the records from a shader
// storage buffer at binding 0 instead of the uniform block.
// Bindings: the records at (uniform or storage) buffer binding 0, the palette at texture unit 0,
// `uniform uvec4 si_palette_info` at location 0 (si::paletteShaderInfo()).
// Motion vectors: define SI_PREVIOUS_RECORDS for the previous frame's records, in the same
// slots, at (uniform or storage) buffer binding SI_PREVIOUS_BINDING (default 1; written by
// si::InstanceBatcher::buildPrevious) and siSkinPrevious(); SI_PREVIOUS_IN_STORAGE reads them
// (and the previous layer records) from a storage buffer when the records are in a uniform block.
// Layered animation: define SI_LAYERS for each slot's layer record (si::LayerRecord, a uvec4)
// at (uniform or storage: SI_INSTANCES_IN_STORAGE or SI_LAYERS_IN_STORAGE) buffer binding
// SI_LAYER_BINDING (default 2; written by si::InstanceBatcher::buildLayers), the crowd's
// mask table at storage binding SI_MASK_BINDING (default 8; si::layerMaskTable) and
// siSkinLayered(); with SI_PREVIOUS_RECORDS too, the previous layer records at binding
// SI_PREVIOUS_LAYER_BINDING (default 3; InstanceBatcher::buildPreviousLayers) and
// siSkinPreviousLayered().
#ifndef SI_SKINNING_GLSL
#define SI_SKINNING_GLSL
#define SI_GLSL_INTERFACE_VERSION 5
#include "si_instance_record.glsl"
#include "si_transform.glsl"

#ifdef SI_INSTANCES_IN_STORAGE
layout(std430, binding = 0) readonly buffer SiInstances { SiInstance si_instances[]; };
#else
layout(std140, binding = 0) uniform SiInstances { SiInstance si_instances[SI_MAX_INSTANCES]; };
#endif
#ifdef SI_PREVIOUS_RECORDS
#ifndef SI_PREVIOUS_BINDING
#define SI_PREVIOUS_BINDING 1
#endif
#if defined(SI_INSTANCES_IN_STORAGE) || defined(SI_PREVIOUS_IN_STORAGE)
layout(std430, binding = SI_PREVIOUS_BINDING) readonly buffer SiPreviousInstances {
  SiInstance si_previous_instances[];
};
#else
layout(std140, binding = SI_PREVIOUS_BINDING) uniform SiPreviousInstances {
  SiInstance si_previous_instances[SI_MAX_INSTANCES];
};
#endif
#endif
#ifdef SI_LAYERS
#ifndef SI_LAYER_BINDING
#define SI_LAYER_BINDING 2
#endif
#ifndef SI_MASK_BINDING
#define SI_MASK_BINDING 8
#endif
#if defined(SI_INSTANCES_IN_STORAGE) || defined(SI_LAYERS_IN_STORAGE)
layout(std430, binding = SI_LAYER_BINDING) readonly buffer SiLayers { uvec4 si_layers[]; };
#else
layout(std140, binding = SI_LAYER_BINDING) uniform SiLayers { uvec4 si_layers[SI_MAX_INSTANCES]; };
#endif
#ifdef SI_PREVIOUS_RECORDS
#ifndef SI_PREVIOUS_LAYER_BINDING
#define SI_PREVIOUS_LAYER_BINDING 3
#endif
#if defined(SI_INSTANCES_IN_STORAGE) || defined(SI_LAYERS_IN_STORAGE) || \
    defined(SI_PREVIOUS_IN_STORAGE)
layout(std430, binding = SI_PREVIOUS_LAYER_BINDING) readonly buffer SiPreviousLayers {
  uvec4 si_previous_layers[];
};
#else
layout(std140, binding = SI_PREVIOUS_LAYER_BINDING) uniform SiPreviousLayers {
  uvec4 si_previous_layers[SI_MAX_INSTANCES];
};
#endif
#endif
// [0]: palette slots per mask; then per mask, per slot: -2 outside the mask, -1 the overlay's
// own matrix, else the anchor slot.
layout(std430, binding = SI_MASK_BINDING) readonly buffer SiLayerMasks { int si_mask_anchor[]; };
#endif
layout(binding = 0) uniform sampler2D si_palette;
layout(location = 0) uniform uvec4 si_palette_info;

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
vec4 siQuatMul(vec4 a, vec4 b) {
  return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}
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
// The delta C * inverse(A) (rows d0..d2), its uniform scale and its rotation in hemisphere h's
// half; false where it mirrors or is degenerate. si::rigidDeltaRotation.
bool siSplitDelta(vec4 a0, vec4 a1, vec4 a2, vec4 c0, vec4 c1, vec4 c2, vec4 h, out vec4 d0,
                  out vec4 d1, out vec4 d2, out float scale, out vec4 q) {
  vec4 i0, i1, i2;
  siAffineInverse(a0, a1, a2, i0, i1, i2);
  d0 = siMulRow(c0, i0, i1, i2);
  d1 = siMulRow(c1, i0, i1, i2);
  d2 = siMulRow(c2, i0, i1, i2);
  float det = determinant(mat3(d0.xyz, d1.xyz, d2.xyz));
  scale = 1.0;
  q = vec4(0.0, 0.0, 0.0, 1.0);
  if (!(det > 1e-30)) return false;
  scale = pow(det, 1.0 / 3.0);
  q = siQuatFromRows(d0.xyz / scale, d1.xyz / scale, d2.xyz / scale);
  if (dot(q, h) < 0.0) q = -q;
  return true;
}
// si::rigidBlend: rows A moved a fraction t of the rigid motion towards rows C (a dual
// quaternion blend with the identity, on the screw motion's path), turning in hemisphere h.
void siRigidBlend(vec4 a0, vec4 a1, vec4 a2, vec4 c0, vec4 c1, vec4 c2, float t, vec4 h,
                  out vec4 r0, out vec4 r1, out vec4 r2) {
  vec4 d0, d1, d2, q;
  float scale;
  r0 = mix(a0, c0, t);
  r1 = mix(a1, c1, t);
  r2 = mix(a2, c2, t);
  if (!siSplitDelta(a0, a1, a2, c0, c1, c2, h, d0, d1, d2, scale, q)) return;
  vec3 v = vec3(d0.w, d1.w, d2.w);
  vec4 dual = 0.5 * siQuatMul(vec4(v, 0.0), q);
  float half_angle = acos(clamp(q.w, -1.0, 1.0));
  float s = t;
  if (half_angle > 1e-4) {
    float sa = sin(t * half_angle), sb = sin((1.0 - t) * half_angle);
    s = sa / (sa + sb);
  }
  vec4 qr = vec4(0.0, 0.0, 0.0, 1.0 - s) + s * q;
  float n = length(qr);
  if (!(n > 1e-6)) return;  // A whole turn: the lerp.
  qr /= n;
  vec4 qd = s * dual / n;
  vec3 translation = 2.0 * siQuatMul(qd, vec4(-qr.xyz, qr.w)).xyz;
  vec4 b0, b1, b2, g0, g1, g2;
  siRigidRows(qr, vec4(translation, 1.0 - t + t * scale), b0, b1, b2);
  siRigidRows(q, vec4(v, scale), g0, g1, g2);
  // Blended rigid part plus what the delta holds beyond it, in proportion; then times A.
  b0 += (d0 - g0) * t;
  b1 += (d1 - g1) * t;
  b2 += (d2 - g2) * t;
  r0 = siMulRow(b0, a0, a1, a2);
  r1 = siMulRow(b1, a0, a1, a2);
  r2 = siMulRow(b2, a0, a1, a2);
}

// The rows of palette slot `joint` with the layer record `layer` composed on it:
// si::emulateLayeredMatrix. Outside the layer's mask, or at weight 0, the base rows.
void siLayeredJointRows(SiInstance inst, uvec4 layer, uint joint, out vec4 r0, out vec4 r1,
                        out vec4 r2) {
  siInstanceJointRows(inst, joint, r0, r1, r2);
  float w = float(layer.w & 0xFFFFu) / 65535.0;
  if (w == 0.0) return;
  uint slots = uint(si_mask_anchor[0]);
  uint table = 1u + (layer.w >> 16) * 2u * slots;
  int anchor = si_mask_anchor[table + joint];
  if (anchor == -2) return;
  // K = base anchor * inverse(overlay anchor); the identity for the model anchor.
  vec4 k0 = vec4(1.0, 0.0, 0.0, 0.0), k1 = vec4(0.0, 1.0, 0.0, 0.0), k2 = vec4(0.0, 0.0, 1.0, 0.0);
  if (anchor >= 0) {
    vec4 b0, b1, b2, a0, a1, a2, i0, i1, i2;
    siInstanceJointRows(inst, uint(anchor), b0, b1, b2);
    siInterpolatedRows(layer.x, layer.y, layer.z, uint(anchor), a0, a1, a2);
    siAffineInverse(a0, a1, a2, i0, i1, i2);
    k0 = siMulRow(b0, i0, i1, i2);
    k1 = siMulRow(b1, i0, i1, i2);
    k2 = siMulRow(b2, i0, i1, i2);
  }
  vec4 o0, o1, o2;
  siInterpolatedRows(layer.x, layer.y, layer.z, joint, o0, o1, o2);
  vec4 c0 = siMulRow(k0, o0, o1, o2), c1 = siMulRow(k1, o0, o1, o2), c2 = siMulRow(k2, o0, o1, o2);
  if (w >= 1.0) {
    r0 = c0;
    r1 = c1;
    r2 = c2;
    return;
  }
  // Each joint turns less than half a turn from its parent, so its delta's quaternion lies in
  // its parent's half: multiply the sign of each step up the mask's parent slots (the branch
  // root turns the shorter way), then blend in that hemisphere.
  vec4 d0, d1, d2, q, h;
  float scale;
  const vec4 identity = vec4(0.0, 0.0, 0.0, 1.0);
  siSplitDelta(r0, r1, r2, c0, c1, c2, identity, d0, d1, d2, scale, h);
  q = h;
  float sign = 1.0;
  int parent = si_mask_anchor[table + slots + joint];
  for (uint steps = 0u; parent >= 0 && steps < slots; ++steps) {
    vec4 p0, p1, p2, e0, e1, e2, up;
    siInstanceJointRows(inst, uint(parent), p0, p1, p2);
    siInterpolatedRows(layer.x, layer.y, layer.z, uint(parent), o0, o1, o2);
    e0 = siMulRow(k0, o0, o1, o2);
    e1 = siMulRow(k1, o0, o1, o2);
    e2 = siMulRow(k2, o0, o1, o2);
    siSplitDelta(p0, p1, p2, e0, e1, e2, identity, d0, d1, d2, scale, up);
    if (dot(q, up) < 0.0) sign = -sign;
    q = up;
    parent = si_mask_anchor[table + slots + uint(parent)];
  }
  h *= sign;
  siRigidBlend(r0, r1, r2, c0, c1, c2, w, h, r0, r1, r2);
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
