// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The local-space blend of a joint's transform relative to its parent, as si_skinning.glsl
// forms it.
#include "si/core/local_blend.h"

#include <algorithm>
#include <cmath>

namespace si {
namespace {

// The unit quaternion (x, y, z, w) of rotation matrix `m` (columns), Shepperd's method: the
// largest of w, x, y, z is taken from the diagonal, the others from sums and differences.
glm::vec4 quatFromRotation(const glm::mat3& m) {
  // m[col][row]: e(r, c) below is row r, column c.
  auto e = [&](int r, int c) { return m[c][r]; };
  const float tr = e(0, 0) + e(1, 1) + e(2, 2);
  glm::vec4 q;
  if (tr > 0.0f) {
    const float s = std::sqrt(tr + 1.0f) * 2.0f;
    q = glm::vec4((e(2, 1) - e(1, 2)) / s, (e(0, 2) - e(2, 0)) / s, (e(1, 0) - e(0, 1)) / s, 0.25f * s);
  } else if (e(0, 0) > e(1, 1) && e(0, 0) > e(2, 2)) {
    const float s = std::sqrt(1.0f + e(0, 0) - e(1, 1) - e(2, 2)) * 2.0f;
    q = glm::vec4(0.25f * s, (e(0, 1) + e(1, 0)) / s, (e(0, 2) + e(2, 0)) / s, (e(2, 1) - e(1, 2)) / s);
  } else if (e(1, 1) > e(2, 2)) {
    const float s = std::sqrt(1.0f + e(1, 1) - e(0, 0) - e(2, 2)) * 2.0f;
    q = glm::vec4((e(0, 1) + e(1, 0)) / s, 0.25f * s, (e(1, 2) + e(2, 1)) / s, (e(0, 2) - e(2, 0)) / s);
  } else {
    const float s = std::sqrt(1.0f + e(2, 2) - e(0, 0) - e(1, 1)) * 2.0f;
    q = glm::vec4((e(0, 2) + e(2, 0)) / s, (e(1, 2) + e(2, 1)) / s, 0.25f * s, (e(1, 0) - e(0, 1)) / s);
  }
  return glm::normalize(q);
}

glm::mat3 rotationOf(const glm::vec4& q) {
  const float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  const float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  const float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  // Columns.
  return glm::mat3(glm::vec3(1.0f - 2.0f * (yy + zz), 2.0f * (xy + wz), 2.0f * (xz - wy)),
                   glm::vec3(2.0f * (xy - wz), 1.0f - 2.0f * (xx + zz), 2.0f * (yz + wx)),
                   glm::vec3(2.0f * (xz + wy), 2.0f * (yz - wx), 1.0f - 2.0f * (xx + yy)));
}

}  // namespace

glm::mat4 affineInverse(const glm::mat4& m) {
  const glm::mat3 inv = glm::inverse(glm::mat3(m));
  glm::mat4 r(inv);
  r[3] = glm::vec4(-(inv * glm::vec3(m[3])), 1.0f);
  return r;
}

glm::mat4 localBlend(const glm::mat4& a, const glm::mat4& c, const glm::vec3& pivot, float t) {
  const glm::mat3 la(a), lc(c);
  const float det_a = glm::determinant(la), det_c = glm::determinant(lc);
  if (!(det_a > 1e-30f && det_c > 1e-30f)) return a * (1.0f - t) + c * t;
  const float sa = std::pow(det_a, 1.0f / 3.0f), sc = std::pow(det_c, 1.0f / 3.0f);
  const glm::vec4 qa = quatFromRotation(la / sa);
  glm::vec4 qc = quatFromRotation(lc / sc);
  float d = glm::dot(qa, qc);
  if (d < 0.0f) {  // The shorter arc, as the reference's slerp takes it.
    qc = -qc;
    d = -d;
  }
  const float angle = std::acos(std::min(d, 1.0f));
  glm::vec4 q = qa * (1.0f - t) + qc * t;
  if (angle > 1e-4f)
    q = (std::sin((1.0f - t) * angle) * qa + std::sin(t * angle) * qc) / std::sin(angle);
  // The rotation and uniform scale blended, plus what each holds beyond them, in proportion.
  const glm::mat3 linear = rotationOf(glm::normalize(q)) * (sa * (1.0f - t) + sc * t) +
                           (la - rotationOf(qa) * sa) * (1.0f - t) + (lc - rotationOf(qc) * sc) * t;
  // The bind-pose origin goes where the two ends take it, lerped.
  const glm::vec3 origin =
      glm::vec3(a * glm::vec4(pivot, 1.0f)) * (1.0f - t) + glm::vec3(c * glm::vec4(pivot, 1.0f)) * t;
  glm::mat4 r(linear);
  r[3] = glm::vec4(origin - linear * pivot, 1.0f);
  return r;
}

}  // namespace si
