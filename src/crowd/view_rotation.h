// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The character's rotation that shows it from one view direction to a camera looking along -z:
// the convention of the impostor atlas's cells (impostor_plan.h), of the image error's
// views (image_lod_error.cpp, which measures between the atlas's), and of the view direction
// the impostor vertex shader recovers from a character's model space (shaders/
// impostor.vert.glsl: elevation asin(d.y), azimuth atan(-d.x, d.z)).

#include <glm/gtc/quaternion.hpp>

namespace si::detail {

/// Seen from `elevation_degrees` above the horizon (about x) and `azimuth_radians` around the
/// character's vertical axis (about y).
inline glm::quat viewRotation(double elevation_degrees, double azimuth_radians) {
  constexpr double kDegrees = 3.14159265358979323846 / 180.0;
  return glm::angleAxis(float(elevation_degrees * kDegrees), glm::vec3(1, 0, 0)) *
         glm::angleAxis(float(azimuth_radians), glm::vec3(0, 1, 0));
}

}  // namespace si::detail
