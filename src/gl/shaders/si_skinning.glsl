// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The skinning include for your own vertex (or compute) shaders: the instance record, the
// instance block, the palette and functions that fetch, interpolate, crossfade and blend the
// bone matrices exactly as si::emulateSkinningMatrix() and si::emulateSkinning() do on the CPU.
// Interface version 12 (2: the fraction words carry the interval mode, cubic clips; 3: the
// record's fourth blend word is the appearance: tint RGB8 and the custom texture layer; 4: the
// previous frame's records and siSkinPrevious, for motion vectors; 5: layered animation, the
// layer records, the mask table and siSkinLayered; 6: the mask table holds each slot's bind-pose
// origin and weights between 0 and 1 blend each joint in local space; 7: every binding is a
// define, si_palette_info is in a uniform block, descriptor sets under Vulkan; 8: GLSL ES 3.00
// (OpenGL ES 3.0, WebGL 2) through si_profile.glsl: there the application binds the blocks and
// the palette sampler after linking; 9: bit 31 of a layer record's last word flags a 2D blend's
// extra layer records, siLayerMask and siLayerWeight read the word, siLayeredChainRows composes
// the chain; 10: SI_SKIN_SUM and siPlacePoint, what the skinning functions are made of; 11:
// SI_MORPH_TARGETS, si_morph.glsl: morph targets, si_morph_info in SiPaletteInfo; 12: each
// vertex's morph entries ordered by effect with their tails, si_morph_cuts in SiPaletteInfo and
// siMorph's LOD argument: a coarse level leaves out what moves a vertex less than its cut);
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
// Morph targets: define SI_MORPH_TARGETS for si_morph.glsl (the morph texture at texture unit
// SI_MORPH_BINDING [5], si_morph_info and si_morph_cuts as SiPaletteInfo's members after
// si_palette_info, siMorph()).
#ifndef SI_SKINNING_GLSL
#define SI_SKINNING_GLSL
#define SI_GLSL_INTERFACE_VERSION 12
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
#ifdef SI_MORPH_TARGETS
  uvec4 si_morph_info;     // si::morphShaderInfo(): si_morph.glsl.
  vec4 si_morph_cuts[2];  // si::morphLodCuts(): per LOD level, levels 0-3 then 4-7.
#endif
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

// The skinning matrix rows m0, m1, m2: the rows of up to 4 influences blended by `weights`,
// branching past zero weights. READ_ROWS is the statement that reads influence joint `joint`'s
// rows into r0, r1, r2 (siSkin, siSkinLayered, siSkinComposed each read them their own way).
#define SI_SKIN_SUM(joints, weights, READ_ROWS) \
  m0 = vec4(0.0);                               \
  m1 = vec4(0.0);                               \
  m2 = vec4(0.0);                               \
  for (int si_k = 0; si_k < 4; ++si_k) {        \
    float si_w = weights[si_k];                 \
    if (si_w == 0.0) continue;                  \
    uint joint = joints[si_k];                  \
    vec4 r0, r1, r2;                            \
    READ_ROWS;                                  \
    m0 += si_w * r0;                            \
    m1 += si_w * r1;                            \
    m2 += si_w * r2;                            \
  }

// Blends the matrices of up to 4 influences by weight, branching past zero weights.
void siSkin(SiInstance inst, uvec4 joints, vec4 weights, out vec4 m0, out vec4 m1, out vec4 m2) {
  SI_SKIN_SUM(joints, weights, siInstanceJointRows(inst, joint, r0, r1, r2))
}

// Where bind-pose `position`, skinned by rows m0, m1, m2, stands placed by record `inst`: its
// camera-relative world position.
vec3 siPlacePoint(SiInstance inst, vec4 m0, vec4 m1, vec4 m2, vec3 position) {
  return siTransformPoint(inst.world_rows[0], inst.world_rows[1], inst.world_rows[2],
                          siTransformPoint(m0, m1, m2, position));
}

#ifdef SI_PREVIOUS_RECORDS
// Where bind-pose `position` of instance slot `instance` was drawn in the previous frame:
// camera-relative (to the previous camera) world position, skinned with the instance's previous
// record exactly as siSkin skinned it then. Project it with the previous frame's camera.
vec3 siSkinPrevious(uint instance, uvec4 joints, vec4 weights, vec3 position) {
  SiInstance prev = si_previous_instances[instance];
  vec4 m0, m1, m2;
  siSkin(prev, joints, weights, m0, m1, m2);
  return siPlacePoint(prev, m0, m1, m2, position);
}
#endif

#ifdef SI_LAYERS
#include "si_layered.glsl"
#endif
#ifdef SI_MORPH_TARGETS
#include "si_morph.glsl"
#endif
#endif
