// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Translation-rotation-scale transforms in float (stored data) and double (reference evaluation).

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace si {

/// A local joint transform: matrix = T * R * S (glTF order). Rotation need not be unit length in
/// stored data; evaluation normalizes it.
struct Transform {
  glm::vec3 translation = glm::vec3(0.0f);
  glm::quat rotation = glm::quat(1.0f, 0.0f, 0.0f, 0.0f);  ///< (w, x, y, z) constructor order.
  glm::vec3 scale = glm::vec3(1.0f);

  /// T * R * S with the rotation normalized (a zero quaternion gives identity rotation).
  glm::mat4 toMatrix() const;
};

/// The double-precision transform the reference evaluator works in.
struct TransformD {
  glm::dvec3 translation = glm::dvec3(0.0);
  glm::dquat rotation = glm::dquat(1.0, 0.0, 0.0, 0.0);
  glm::dvec3 scale = glm::dvec3(1.0);

  /// T * R * S with the rotation normalized (a zero quaternion gives identity rotation).
  glm::dmat4 toMatrix() const;
  /// Widens a stored transform.
  static TransformD fromFloat(const Transform& t);
};

/// True when every component of `v` is finite.
bool isFinite(const glm::vec3& v);
bool isFinite(const glm::vec4& v);
bool isFinite(const glm::quat& q);
bool isFinite(const glm::mat4& m);

/// Normalizes `q`; a quaternion of zero (or non-finite) length gives the identity.
glm::dquat safeNormalize(const glm::dquat& q);

}  // namespace si
