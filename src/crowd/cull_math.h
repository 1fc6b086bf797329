// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd's selection arithmetic: far-line distance, frustum test of the clip's bounding
// sphere (and, during a crossfade, the faded-out clip's), LOD with hysteresis. Written with
// +, -, * and comparisons only, in a fixed order, so the GPU-driven culling shader
// (src/gl/gpu_culling.cpp, its `precise` GLSL twin) rounds every step the same way and selects
// exactly the same instances and LODs. Compiled with -ffp-contract=off (src/crowd/CMakeLists.txt).

#include <array>
#include <cstdint>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "si/crowd/gpu_crowd_state.h"

namespace si::cull {

using Params = CullParams;

/// The result: the LOD (in: the instance's previous LOD; out: the new one) and why it was
/// culled.
struct Selection {
  uint32_t lod = 0;
  bool culled_by_distance = false;
};

inline float dot3(const glm::vec3& a, const glm::vec3& b) {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}

inline glm::vec3 cross3(const glm::vec3& a, const glm::vec3& b) {
  return glm::vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

/// q * v as glm computes it: v + ((u x v) * w + u x (u x v)) * 2 with u = q.xyz.
inline glm::vec3 rotate(const glm::quat& q, const glm::vec3& v) {
  const glm::vec3 u(q.x, q.y, q.z);
  const glm::vec3 uv = cross3(u, v);
  const glm::vec3 uuv = cross3(u, uv);
  return v + ((uv * q.w) + uuv) * 2.0f;
}

/// The largest finite float: a squared camera distance past it (1.8e19 units, or a position
/// whose camera-relative float is not finite) is culled by distance, far line or not.
inline constexpr float kMaxSquaredDistance = 3.40282347e38f;

/// Whether an instance at camera-relative `rel` with scale `s` lies past the far line, or so far
/// that its squared distance is not a finite float (then even without a far line): the first
/// test of select(), also run alone before gathering.
inline bool beyondFarLine(const glm::vec3& rel, float s, const Params& p) {
  const float d2 = dot3(rel, rel);
  if (!(d2 <= kMaxSquaredDistance)) return true;
  if (!(p.max_distance_radii >= 0.0f)) return false;
  const float far_line = p.max_distance_radii * (p.radius * s);
  return d2 > far_line * far_line;
}

/// Selects an instance at camera-relative position `rel` with rotation `q` and scale `s`,
/// wearing clip A's sphere (centre and radius in model units) and, while fading, clip B's (pass
/// A's twice otherwise). False when culled (by the far line or because both spheres lie outside
/// one frustum plane); otherwise `out->lod` is the new LOD.
inline bool select(const glm::vec3& rel, const glm::quat& q, float s, const glm::vec3& center_a,
                   float radius_a, const glm::vec3& center_b, float radius_b, const Params& p,
                   Selection* out) {
  out->culled_by_distance = beyondFarLine(rel, s, p);
  if (out->culled_by_distance) return false;
  const float radius = p.radius * s;
  const float d2 = dot3(rel, rel);
  const glm::vec3 ca = rel + rotate(q, center_a * s);
  const glm::vec3 cb = rel + rotate(q, center_b * s);
  const float ra = radius_a * s, rb = radius_b * s;
  for (const glm::vec4& plane : p.planes) {
    const glm::vec3 n(plane);
    const bool a_inside = dot3(n, ca) + plane.w >= -ra;
    const bool b_inside = dot3(n, cb) + plane.w >= -rb;
    if (!a_inside && !b_inside) return false;
  }
  // LOD with hysteresis: move one way only once past the line by the hysteresis margin.
  uint32_t lod = out->lod < p.lod_count ? out->lod : p.lod_count - 1;
  while (lod + 1 < p.lod_count) {
    const float line = p.lod_lines[lod] * (1.0f + p.hysteresis) * radius;
    if (!(d2 > line * line)) break;
    ++lod;
  }
  while (lod > 0) {
    const float line = p.lod_lines[lod - 1] * (1.0f - p.hysteresis) * radius;
    if (!(d2 < line * line)) break;
    --lod;
  }
  out->lod = lod;
  return true;
}

}  // namespace si::cull
