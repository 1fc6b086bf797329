// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Frustum planes from a view-projection matrix: G. Gribb and K. Hartmann, "Fast Extraction of
// Viewing Frustum Planes from the World-View-Projection Matrix" (2001).
#include "si/crowd/camera.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace si {

Camera Camera::lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::vec3& up,
                      float fov_y_radians, float aspect, float near_plane, float far_plane) {
  Camera c;
  c.position = eye;
  const glm::vec3 forward(target - eye);
  c.view_rotation = glm::lookAt(glm::vec3(0.0f), forward, up);
  // glm::perspective's right-handed, [-1, 1] depth matrix, written out without its debug
  // assertions: hostile arguments give a non-finite projection (whose planes cull every
  // instance), never an abort.
  const float tan_half = std::tan(fov_y_radians * 0.5f);
  c.projection = glm::mat4(0.0f);
  c.projection[0][0] = 1.0f / (aspect * tan_half);
  c.projection[1][1] = 1.0f / tan_half;
  c.projection[2][2] = -(far_plane + near_plane) / (far_plane - near_plane);
  c.projection[2][3] = -1.0f;
  c.projection[3][2] = -(2.0f * far_plane * near_plane) / (far_plane - near_plane);
  return c;
}

std::array<glm::vec4, 6> Camera::frustumPlanes() const {
  const glm::mat4 m = viewProjection();
  const glm::vec4 r0(m[0][0], m[1][0], m[2][0], m[3][0]);
  const glm::vec4 r1(m[0][1], m[1][1], m[2][1], m[3][1]);
  const glm::vec4 r2(m[0][2], m[1][2], m[2][2], m[3][2]);
  const glm::vec4 r3(m[0][3], m[1][3], m[2][3], m[3][3]);
  std::array<glm::vec4, 6> planes = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2};
  for (glm::vec4& p : planes) {
    const float len = glm::length(glm::vec3(p));
    if (len > 0.0f) p /= len;
  }
  return planes;
}

}  // namespace si
