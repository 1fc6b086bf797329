// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Shadow cascades for the examples: orthographic sun cameras, each round a slice of a main
// camera's depth range (crowd_bench --views, crowd_demo --shadows).
#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "si/crowd/camera.h"

namespace si::examples {

/// The sun cameras of `cascades` cascades of `main`: its depth range [near_m, far_m] ahead
/// split geometrically into slices, each covered by an orthographic camera looking along
/// `sun_direction` round the slice's bounding sphere, `resolution` pixels high.
inline std::vector<Camera> cascadeCameras(const Camera& main, uint32_t cascades,
                                          const glm::vec3& sun_direction, float resolution,
                                          double near_m, double far_m) {
  // The main camera's forward direction (view space looks down -z), and how far a slice's
  // corner lies off its axis per metre ahead (from the projection's field of view).
  const glm::mat4& v = main.view_rotation;
  const glm::dvec3 forward = -glm::dvec3(v[0][2], v[1][2], v[2][2]);
  const double p00 = std::max(1e-6, double(main.projection[0][0]));
  const double p11 = std::max(1e-6, double(main.projection[1][1]));
  const double corner = std::sqrt(1.0 / (p00 * p00) + 1.0 / (p11 * p11));
  const glm::dvec3 sun = glm::normalize(glm::dvec3(sun_direction));
  near_m = std::max(near_m, 0.1);
  far_m = std::max(far_m, near_m * 2.0);
  std::vector<Camera> out;
  for (uint32_t c = 0; c < cascades; ++c) {
    // Slices split the depth range geometrically; each cascade a sphere round its slice.
    const double a = near_m * std::pow(far_m / near_m, double(c) / cascades);
    const double b = near_m * std::pow(far_m / near_m, double(c + 1) / cascades);
    const double half = 0.5 * (b - a);
    const glm::dvec3 centre = main.position + forward * (a + half);
    const float radius = float(std::sqrt(half * half + b * corner * b * corner));
    Camera cam;
    cam.position = centre - sun * (double(radius) + 100.0);
    const glm::vec3 up = std::abs(sun.y) > 0.99 ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    cam.view_rotation = glm::lookAt(glm::vec3(0.0f), glm::vec3(sun), up);
    cam.projection = glm::ortho(-radius, radius, -radius, radius, 1.0f, 2.0f * radius + 200.0f);
    cam.viewport_height_pixels = resolution;
    out.push_back(cam);
  }
  return out;
}

}  // namespace si::examples
