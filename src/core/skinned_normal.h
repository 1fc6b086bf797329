// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Internal: a normal skinned as the shaders skin it (si_transform.glsl's siTransformNormal),
// for the CPU code that must draw or emulate what they draw.

#include <glm/glm.hpp>

namespace si::detail {

/// `n` through sign(det) * cofactor of the blended 3x3 `m` (the inverse transpose up to a
/// positive scale: right under non-uniform scale and mirroring, finite for singular matrices),
/// normalized; `n` itself where that has no length.
inline glm::vec3 skinNormal(const glm::mat3& m, const glm::vec3& n) {
  glm::mat3 cofactor(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
  if (glm::dot(m[0], cofactor[0]) < 0.0f) cofactor = -cofactor;
  const glm::vec3 t = cofactor * n;
  const float length = glm::length(t);
  return length > 1e-30f ? t / length : n;
}

}  // namespace si::detail
