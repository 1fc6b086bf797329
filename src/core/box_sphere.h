// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The sphere around a box that culling reads: a baked clip's (BakedClip::bounding_sphere, the
// bake) and a live pose's (the crowd's LivePoses). One rule, so the two are culled alike.

#include <glm/glm.hpp>

#include "si/core/bounds.h"

namespace si::detail {

/// The sphere around `box`: centred on it (clamped into it), its radius half the box's
/// diagonal, in double and widened by 1e-6 so that the float sphere holds every corner.
/// `radius` receives that radius in double: a box spanning past what float bounds hold has one
/// past 3e38 (the float radius is then infinite).
inline Sphere boxSphere(const Aabb& box, double* radius) {
  const glm::dvec3 lo(box.min), hi(box.max);
  *radius = 0.5 * glm::length(hi - lo) * (1.0 + 1e-6);
  Sphere s;
  s.center = glm::clamp(glm::vec3(0.5 * lo + 0.5 * hi), box.min, box.max);
  s.radius = float(*radius);
  return s;
}

}  // namespace si::detail
