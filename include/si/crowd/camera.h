// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The camera the crowd culls against. Its position is double so crowds far from the origin
/// keep their precision: everything the GPU sees is relative to the camera.

#include <array>

#include <glm/glm.hpp>

namespace si {

/// A perspective or orthographic camera: position in double, orientation and projection in
/// float. `view_rotation` maps camera-relative world directions to view space (a view matrix
/// without translation); the GPU's view-projection is projection * view_rotation applied to
/// camera-relative positions.
struct Camera {
  glm::dvec3 position = glm::dvec3(0.0);
  glm::mat4 view_rotation = glm::mat4(1.0f);
  glm::mat4 projection = glm::mat4(1.0f);
  /// Height of the viewport in pixels: screen-space-error LOD (CrowdDesc::lod_mode) projects
  /// errors to it. Set it to the framebuffer's height.
  float viewport_height_pixels = 1080.0f;

  /// A camera at `eye` looking at `target` with `up`, a vertical field of view in radians,
  /// aspect ratio (width / height) and near/far planes (OpenGL clip space, z in [-w, w]), as
  /// glm::lookAt and glm::perspective make them. Degenerate or non-finite arguments give a
  /// camera whose frustum culls every instance (no assertion, no crash).
  static Camera lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::vec3& up,
                       float fov_y_radians, float aspect, float near_plane, float far_plane);

  /// projection * view_rotation: camera-relative world to clip space.
  glm::mat4 viewProjection() const { return projection * view_rotation; }

  /// The six frustum planes (left, right, bottom, top, near, far) in camera-relative world
  /// space, normalized, pointing inwards: a point p is inside when dot(xyz, p) + w >= 0 for all.
  std::array<glm::vec4, 6> frustumPlanes() const;
};

}  // namespace si
