// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Frustum planes from a view-projection matrix: G. Gribb and K. Hartmann, "Fast Extraction of
// Viewing Frustum Planes from the World-View-Projection Matrix" (2001).
#include "si/crowd/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

const char* depthConventionName(DepthConvention convention) {
  switch (convention) {
    case DepthConvention::kNegativeOneToOne: return "negative-one-to-one";
    case DepthConvention::kZeroToOne: return "zero-to-one";
    case DepthConvention::kReversedZeroToOne: return "reversed zero-to-one";
  }
  return "unknown";
}

Camera Camera::lookAtReverseZ(const glm::dvec3& eye, const glm::dvec3& target, const glm::vec3& up,
                              float fov_y_radians, float aspect, float near_plane,
                              float far_plane) {
  Camera c = lookAt(eye, target, up, fov_y_radians, aspect, near_plane, far_plane);
  c.depth = DepthConvention::kReversedZeroToOne;
  // Clip z = a z + b with w = -z (right-handed view space): depth 1 at -near, 0 at -far; with an
  // infinite far plane a = 0, b = near.
  const bool infinite = std::isinf(far_plane) && far_plane > 0.0f;
  c.projection[2][2] = infinite ? 0.0f : near_plane / (far_plane - near_plane);
  c.projection[3][2] = infinite ? near_plane : far_plane * near_plane / (far_plane - near_plane);
  return c;
}

Camera Camera::fromMatrices(const glm::dmat4& view, const glm::mat4& projection,
                            DepthConvention depth, float viewport_height_pixels) {
  Camera c;
  c.projection = projection;
  c.depth = depth;
  c.viewport_height_pixels = viewport_height_pixels;
  const glm::dmat3 r(view);
  // Rigid: the rotation's columns orthonormal (within float precision), nothing projective.
  const glm::dmat3 rtr = glm::transpose(r) * r;
  double off = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) off = std::max(off, std::abs(rtr[i][j] - (i == j ? 1.0 : 0.0)));
  const bool rigid = off < 1e-5 && view[0][3] == 0.0 && view[1][3] == 0.0 &&
                     view[2][3] == 0.0 && view[3][3] == 1.0 && glm::determinant(r) > 0.0;
  if (!rigid) {  // NaN everywhere: every plane test fails, every instance is culled.
    c.projection = glm::mat4(std::numeric_limits<float>::quiet_NaN());
    return c;
  }
  // view = [R | t]: the camera sits at -R^T t.
  c.position = -(glm::transpose(r) * glm::dvec3(view[3]));
  c.view_rotation = glm::mat4(glm::mat3(r));
  return c;
}

std::array<glm::vec4, 6> Camera::frustumPlanes() const {
  const glm::mat4 m = viewProjection();
  const glm::vec4 r0(m[0][0], m[1][0], m[2][0], m[3][0]);
  const glm::vec4 r1(m[0][1], m[1][1], m[2][1], m[3][1]);
  const glm::vec4 r2(m[0][2], m[1][2], m[2][2], m[3][2]);
  const glm::vec4 r3(m[0][3], m[1][3], m[2][3], m[3][3]);
  // Near and far: -w <= z <= w, 0 <= z <= w, or reversed w >= z >= 0 (near at w).
  const glm::vec4 near_plane = depth == DepthConvention::kNegativeOneToOne ? r3 + r2
                               : depth == DepthConvention::kZeroToOne      ? r2
                                                                           : r3 - r2;
  const glm::vec4 far_plane = depth == DepthConvention::kReversedZeroToOne ? r2 : r3 - r2;
  std::array<glm::vec4, 6> planes = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, near_plane, far_plane};
  for (glm::vec4& p : planes) {
    const float len = glm::length(glm::vec3(p));
    if (len > 0.0f) p /= len;
  }
  return planes;
}

}  // namespace si
