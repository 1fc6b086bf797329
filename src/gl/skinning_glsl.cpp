// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GLSL twin of si::emulateSkinningMatrix / si::emulateSkinning (src/core/baked_palette.cpp).
#include "si/gl/skinning_glsl.h"

#include <string>

#include "gl/glsl_parts.h"
#include "si/crowd/instance_record.h"

namespace si {

const char* transformGlsl() {
  return R"(
vec3 siTransformPoint(vec4 r0, vec4 r1, vec4 r2, vec3 p) {
  vec4 h = vec4(p, 1.0);
  return vec3(dot(r0, h), dot(r1, h), dot(r2, h));
}

// Normals (and tangents with siTransformVector) through sign(det) * cofactor: correct under
// non-uniform scale and mirroring.
vec3 siTransformNormal(vec4 r0, vec4 r1, vec4 r2, vec3 n) {
  vec3 c0 = vec3(r0.x, r1.x, r2.x), c1 = vec3(r0.y, r1.y, r2.y), c2 = vec3(r0.z, r1.z, r2.z);
  mat3 cof = mat3(cross(c1, c2), cross(c2, c0), cross(c0, c1));
  if (dot(c0, cof[0]) < 0.0) cof = -cof;
  vec3 t = cof * n;
  float len = length(t);
  return len > 1e-30 ? t / len : n;
}
vec3 siTransformVector(vec4 r0, vec4 r1, vec4 r2, vec3 v) {
  return vec3(dot(r0.xyz, v), dot(r1.xyz, v), dot(r2.xyz, v));
}
)";
}

const char* skinningGlsl() {
  static const std::string source = std::string(kInstanceRecordGlsl) + transformGlsl() + R"(
layout(std140, binding = 0) uniform SiInstances { SiInstance si_instances[SI_MAX_INSTANCES]; };
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

)";
  return source.c_str();
}

}  // namespace si
