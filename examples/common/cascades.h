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
/// `sun_direction`, `resolution` pixels high. Each camera's box is the light-space bounding box
/// of the part of its slice between heights `min_y` and `max_y` (where the ground and the
/// characters are), not a sphere round the whole slice, which for a wide field of view reaches
/// back over every nearer slice and puts every character in every cascade. A point of the
/// slice in that height range lies inside the box, and so does every caster that can shadow
/// it: the sun's rays run along the box's depth, which reaches 100 m towards the sun past the
/// slice. A slice that misses the height range gets the box of all of it.
inline std::vector<Camera> cascadeCameras(const Camera& main, uint32_t cascades,
                                          const glm::vec3& sun_direction, float resolution,
                                          double near_m, double far_m, double min_y = -1e30,
                                          double max_y = 1e30) {
  // The main camera's axes (view space looks down -z), and the slice's half extents per metre
  // ahead (from the projection's field of view).
  const glm::mat4& v = main.view_rotation;
  const glm::dvec3 forward = -glm::dvec3(v[0][2], v[1][2], v[2][2]);
  const glm::dvec3 right(v[0][0], v[1][0], v[2][0]), upward(v[0][1], v[1][1], v[2][1]);
  const double p00 = std::max(1e-6, double(main.projection[0][0]));
  const double p11 = std::max(1e-6, double(main.projection[1][1]));
  const glm::dvec3 sun = glm::normalize(glm::dvec3(sun_direction));
  near_m = std::max(near_m, 0.1);
  far_m = std::max(far_m, near_m * 2.0);
  const glm::vec3 up = std::abs(sun.y) > 0.99 ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  const glm::mat4 light_rotation = glm::lookAt(glm::vec3(0.0f), glm::vec3(sun), up);
  std::vector<Camera> out;
  for (uint32_t c = 0; c < cascades; ++c) {
    // Slices split the depth range geometrically.
    const double depths[2] = {near_m * std::pow(far_m / near_m, double(c) / cascades),
                              near_m * std::pow(far_m / near_m, double(c + 1) / cascades)};
    glm::dvec3 corners[8];
    glm::dvec3 centre(0.0);
    for (int k = 0; k < 8; ++k) {
      const double d = depths[k >> 2];
      corners[k] = main.position + forward * d + right * ((k & 1 ? 1.0 : -1.0) * d / p00) +
                   upward * ((k & 2 ? 1.0 : -1.0) * d / p11);
      centre += corners[k] / 8.0;
    }
    double reach = 0.0;  // The slice's radius round its centre.
    for (const glm::dvec3& k : corners) reach = std::max(reach, glm::length(k - centre));
    // The slice between the heights: its twelve edges clipped to the slab [min_y, max_y] (the
    // vertices of a convex slice cut by a slab lie on the slice's edges).
    std::vector<glm::dvec3> points;
    const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                              {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (const auto& e : edges) {
      const glm::dvec3 p = corners[e[0]], q = corners[e[1]];
      double t0 = 0.0, t1 = 1.0;
      const double dy = q.y - p.y;
      if (std::abs(dy) < 1e-12) {
        if (p.y < min_y || p.y > max_y) continue;
      } else {
        double ta = (min_y - p.y) / dy, tb = (max_y - p.y) / dy;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) continue;
      }
      points.push_back(p + (q - p) * t0);
      points.push_back(p + (q - p) * t1);
    }
    if (points.empty()) points.assign(corners, corners + 8);
    Camera cam;
    cam.position = centre - sun * (reach + 100.0);
    cam.view_rotation = light_rotation;
    glm::vec2 lo(1e30f), hi(-1e30f);
    float deepest = 1.0f;
    for (const glm::dvec3& k : points) {
      const glm::vec4 p = light_rotation * glm::vec4(glm::vec3(k - cam.position), 1.0f);
      lo = glm::min(lo, glm::vec2(p));
      hi = glm::max(hi, glm::vec2(p));
      deepest = std::max(deepest, -p.z);
    }
    cam.projection = glm::ortho(lo.x, hi.x, lo.y, hi.y, 1.0f, deepest + 10.0f);
    cam.viewport_height_pixels = resolution;
    out.push_back(cam);
  }
  return out;
}

}  // namespace si::examples
