// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/transform.h"

#include <cmath>

namespace si {

glm::mat4 Transform::toMatrix() const {
  return glm::mat4(TransformD::fromFloat(*this).toMatrix());
}

glm::dquat safeNormalize(const glm::dquat& q) {
  const double len = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!(len > 0.0) || !std::isfinite(len)) return glm::dquat(1.0, 0.0, 0.0, 0.0);
  return glm::dquat(q.w / len, q.x / len, q.y / len, q.z / len);
}

glm::dmat4 TransformD::toMatrix() const {
  const glm::dmat3 r = glm::mat3_cast(safeNormalize(rotation));
  glm::dmat4 m(1.0);
  for (int c = 0; c < 3; ++c) m[c] = glm::dvec4(r[c] * scale[c], 0.0);
  m[3] = glm::dvec4(translation, 1.0);
  return m;
}

TransformD TransformD::fromFloat(const Transform& t) {
  TransformD d;
  d.translation = glm::dvec3(t.translation);
  d.rotation = glm::dquat(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z);
  d.scale = glm::dvec3(t.scale);
  return d;
}

bool isFinite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool isFinite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}
bool isFinite(const glm::quat& q) {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}
bool isFinite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    if (!isFinite(m[c])) return false;
  return true;
}

}  // namespace si
