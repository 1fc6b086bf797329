// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The camera the crowd culls against. Its position is double so crowds far from the origin
/// keep their precision: everything the GPU sees is relative to the camera.

#include <array>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace si {

/// How the projection's clip-space depth reaches the depth buffer: the context's clip control
/// depth mode (glClipControl) and which end is near. The draws check it against the context's
/// clip control (kInvalidArgument when they differ); the depth function is the host's.
enum class DepthConvention : uint8_t {
  /// OpenGL's default: clip z in [-w, w], near at -w (window depth 0), depth test GL_LESS.
  kNegativeOneToOne = 0,
  /// glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE): clip z in [0, w], near at 0, GL_LESS.
  kZeroToOne,
  /// Reverse-Z: glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), clip z in [0, w] with the near
  /// plane at w (window depth 1) and the far plane at 0 (an infinite far plane allowed), depth
  /// test GL_GREATER or GL_GEQUAL, depth cleared to 0: float depth's precision spread over the
  /// whole range.
  kReversedZeroToOne,
};
/// "negative-one-to-one", "zero-to-one", "reversed zero-to-one".
const char* depthConventionName(DepthConvention convention);

/// A perspective or orthographic camera: position in double, orientation and projection in
/// float. `view_rotation` maps camera-relative world directions to view space (a view matrix
/// without translation); the GPU's view-projection is projection * view_rotation applied to
/// camera-relative positions.
struct Camera {
  glm::dvec3 position = glm::dvec3(0.0);
  glm::mat4 view_rotation = glm::mat4(1.0f);
  glm::mat4 projection = glm::mat4(1.0f);
  /// How `projection`'s depth is meant (frustumPlanes(), occlusion culling, the draws' check
  /// of the context's clip control).
  DepthConvention depth = DepthConvention::kNegativeOneToOne;
  /// Height of the viewport in pixels: screen-space-error LOD (CrowdDesc::lod_mode) projects
  /// errors to it. Set it to the framebuffer's height.
  float viewport_height_pixels = 1080.0f;

  /// A camera at `eye` looking at `target` with `up`, a vertical field of view in radians,
  /// aspect ratio (width / height) and near/far planes (OpenGL clip space, z in [-w, w]), as
  /// glm::lookAt and glm::perspective make them. Degenerate or non-finite arguments give a
  /// camera whose frustum culls every instance (no assertion, no crash).
  static Camera lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::vec3& up,
                       float fov_y_radians, float aspect, float near_plane, float far_plane);
  /// The same camera with a reverse-Z projection (DepthConvention::kReversedZeroToOne): window
  /// depth near_plane / distance along the view axis for an infinite far plane (`far_plane`
  /// infinity, the default), else 1 at the near plane and 0 at the far one. Degenerate or
  /// non-finite arguments cull every instance, as lookAt's.
  static Camera lookAtReverseZ(const glm::dvec3& eye, const glm::dvec3& target,
                               const glm::vec3& up, float fov_y_radians, float aspect,
                               float near_plane, float far_plane = INFINITY);
  /// The camera of an engine's own matrices: `view` maps world to view space (a rigid
  /// transform: rotation and translation, in double so a far-away camera keeps its precision),
  /// `projection` view to clip space with `depth`'s meaning (any of glm's or the engine's
  /// projections, perspective or orthographic, y flipped or not). The position is where `view`
  /// puts the origin of view space; view_rotation is `view`'s rotation. A view matrix that is
  /// not rigid (scaled or sheared, or non-finite) gives a camera that culls every instance.
  static Camera fromMatrices(const glm::dmat4& view, const glm::mat4& projection,
                             DepthConvention depth = DepthConvention::kNegativeOneToOne,
                             float viewport_height_pixels = 1080.0f);

  /// Whether the projection mirrors the image on screen (y flipped for a render texture, as
  /// OGRE and others draw them, or x flipped): its x-y part has a negative determinant, so
  /// triangles turn the other way on screen. The draws then take clockwise triangles as front
  /// faces, so the same faces are culled as with the unflipped projection.
  bool flipsWinding() const {
    return projection[0][0] * projection[1][1] - projection[1][0] * projection[0][1] < 0.0f;
  }

  /// projection * view_rotation: camera-relative world to clip space.
  glm::mat4 viewProjection() const { return projection * view_rotation; }

  /// The six frustum planes (left, right, bottom, top, near, far) in camera-relative world
  /// space, normalized, pointing inwards: a point p is inside when dot(xyz, p) + w >= 0 for all.
  /// The near and far planes follow `depth`; an infinite far plane is (0, 0, 0, w > 0), which
  /// every point passes.
  std::array<glm::vec4, 6> frustumPlanes() const;
};

}  // namespace si
