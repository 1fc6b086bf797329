// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Axis-aligned boxes and spheres used for culling bounds and character size.

#include <glm/glm.hpp>

#include "si/core/span.h"

namespace si {

/// An axis-aligned box; empty when min > max on any axis (the default).
struct Aabb {
  glm::vec3 min = glm::vec3(1e30f);
  glm::vec3 max = glm::vec3(-1e30f);

  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void extend(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void extend(const Aabb& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  glm::vec3 center() const { return 0.5f * (min + max); }
  glm::vec3 extent() const { return empty() ? glm::vec3(0.0f) : max - min; }
};

/// A sphere; radius < 0 means empty.
struct Sphere {
  glm::vec3 center = glm::vec3(0.0f);
  float radius = -1.0f;
};

/// The box around `points` (empty for no points).
Aabb computeBounds(Span<const glm::vec3> points);

}  // namespace si
