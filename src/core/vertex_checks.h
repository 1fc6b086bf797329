// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Per-vertex attribute checks shared by the mesh and prop validations (SkinnedMesh::validate,
// PropMesh::validate): a finite texture coordinate, a colour in [0, 1].
#include <cmath>

#include <glm/glm.hpp>

namespace si::detail {

inline bool isFinite2(const glm::vec2& v) {
  return std::isfinite(v.x) && std::isfinite(v.y);
}

/// Every channel in [0, 1] (false for NaN).
inline bool inUnitRange(const glm::vec4& c) {
  return glm::all(glm::greaterThanEqual(c, glm::vec4(0.0f))) &&
         glm::all(glm::lessThanEqual(c, glm::vec4(1.0f)));
}

}  // namespace si::detail
