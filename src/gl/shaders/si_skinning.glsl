// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The skinning include for your own vertex (or compute) shaders: the instance record, the
// instance block, the palette and functions that fetch, interpolate, crossfade and blend the
// bone matrices exactly as si::emulateSkinningMatrix() and si::emulateSkinning() do on the CPU.
// Interface version 1; docs/glsl-interface.md documents every name, binding and define.
//
// Before including, define SI_MAX_INSTANCES (records per draw: InstanceBatcher::
// capacityPerDraw()), or define SI_INSTANCES_IN_STORAGE to read the records from a shader
// storage buffer at binding 0 instead of the uniform block.
// Bindings: the records at (uniform or storage) buffer binding 0, the palette at texture unit 0,
// `uniform uvec4 si_palette_info` at location 0 (si::paletteShaderInfo()).
#ifndef SI_SKINNING_GLSL
#define SI_SKINNING_GLSL
#define SI_GLSL_INTERFACE_VERSION 1
#include "si_instance_record.glsl"
#include "si_transform.glsl"

#ifdef SI_INSTANCES_IN_STORAGE
layout(std430, binding = 0) readonly buffer SiInstances { SiInstance si_instances[]; };
#else
layout(std140, binding = 0) uniform SiInstances { SiInstance si_instances[SI_MAX_INSTANCES]; };
#endif
layout(binding = 0) uniform sampler2D si_palette;
layout(location = 0) uniform uvec4 si_palette_info;

ivec2 siTexel(uint i) {
  return ivec2(int(i & ((1u << si_palette_info.x) - 1u)), int(i >> si_palette_info.x));
}
vec4 siFetch(uint i) { return texelFetch(si_palette, siTexel(i), 0); }

// Rows of the skinning matrix of palette slot `joint`, interpolated between the frames starting
// at texels `frame` and `next` by `t`.
void siInterpolatedRows(uint frame, uint next, float t, uint joint,
                        out vec4 r0, out vec4 r1, out vec4 r2) {
  uint a = frame + joint * si_palette_info.y;
  uint b = next + joint * si_palette_info.y;
  if (si_palette_info.z == 0u) {
    r0 = mix(siFetch(a), siFetch(b), t);
    r1 = mix(siFetch(a + 1u), siFetch(b + 1u), t);
    r2 = mix(siFetch(a + 2u), siFetch(b + 2u), t);
  } else {
    vec4 qa = siFetch(a), qb = siFetch(b);
    if (dot(qa, qb) < 0.0) qb = -qb;  // Shorter arc.
    vec4 q = normalize(mix(qa, qb, t));
    vec4 ts = mix(siFetch(a + 1u), siFetch(b + 1u), t);
    float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    r0 = vec4(vec3(1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy)) * ts.w, ts.x);
    r1 = vec4(vec3(2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx)) * ts.w, ts.y);
    r2 = vec4(vec3(2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy)) * ts.w, ts.z);
  }
}

// The instance's skinning matrix rows for palette slot `joint`: clip A, crossfaded towards
// clip B by the record's weight (B's fetches are skipped when the weight is 0).
void siInstanceJointRows(SiInstance inst, uint joint, out vec4 r0, out vec4 r1, out vec4 r2) {
  siInterpolatedRows(inst.frames.x, inst.frames.y, uintBitsToFloat(inst.blend.x), joint,
                     r0, r1, r2);
  float wb = uintBitsToFloat(inst.blend.z);
  if (wb > 0.0) {
    vec4 b0, b1, b2;
    siInterpolatedRows(inst.frames.z, inst.frames.w, uintBitsToFloat(inst.blend.y), joint,
                       b0, b1, b2);
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
#endif
