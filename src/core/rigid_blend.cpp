// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The rigid (dual quaternion) blend of two affine matrices, as si_skinning.glsl forms it.
#include "si/core/rigid_blend.h"

#include <algorithm>
#include <cmath>

namespace si {
namespace {

// Quaternions as (x, y, z, w), as the shader stores them.
glm::vec4 quatMul(const glm::vec4& a, const glm::vec4& b) {
  const glm::vec3 av(a), bv(b);
  return glm::vec4(a.w * bv + b.w * av + glm::cross(av, bv), a.w * b.w - glm::dot(av, bv));
}

// The unit quaternion of rotation matrix `m` (columns), Shepperd's method: the largest of
// w, x, y, z is taken from the diagonal, the others from sums and differences.
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

glm::mat4 affineInverse(const glm::mat4& m) {
  const glm::mat3 inv = glm::inverse(glm::mat3(m));
  glm::mat4 r(inv);
  r[3] = glm::vec4(-(inv * glm::vec3(m[3])), 1.0f);
  return r;
}

}  // namespace

namespace {

// The delta c * inverse(a), its uniform scale and its rotation's quaternion in `hemisphere`'s
// half; false where it mirrors or is degenerate.
bool splitDelta(const glm::mat4& a, const glm::mat4& c, const glm::vec4& hemisphere,
                glm::mat4* delta, float* scale, glm::vec4* q) {
  *delta = c * affineInverse(a);
  const glm::mat3 d3(*delta);
  const float det = glm::determinant(d3);
  if (!(det > 1e-30f)) return false;
  *scale = std::pow(det, 1.0f / 3.0f);
  *q = quatFromRotation(d3 / *scale);
  if (glm::dot(*q, hemisphere) < 0.0f) *q = -*q;
  return true;
}

}  // namespace

glm::vec4 rigidDeltaRotation(const glm::mat4& a, const glm::mat4& c, const glm::vec4& hemisphere) {
  glm::mat4 d;
  float scale = 1.0f;
  glm::vec4 q;
  return splitDelta(a, c, hemisphere, &d, &scale, &q) ? q : glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
}

glm::mat4 rigidBlend(const glm::mat4& a, const glm::mat4& c, float t, const glm::vec4& hemisphere) {
  glm::mat4 d;
  float scale = 1.0f;
  glm::vec4 q;
  if (!splitDelta(a, c, hemisphere, &d, &scale, &q)) return a * (1.0f - t) + c * t;
  const glm::vec3 v(d[3]);
  const glm::vec4 dual = 0.5f * quatMul(glm::vec4(v, 0.0f), q);
  // The identity (0 0 0 1; 0) blended with (q; dual), normalized by the real part: on the
  // screw motion's path. The blend's weight s turns the rotation by t of its angle (as a slerp
  // would) where the plain weight t would go slower at the ends.
  const float half = std::acos(glm::clamp(q.w, -1.0f, 1.0f));
  float s = t;
  if (half > 1e-4f) {
    const float sa = std::sin(t * half), sb = std::sin((1.0f - t) * half);
    s = sa / (sa + sb);
  }
  glm::vec4 qr = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f - s) + s * q;
  glm::vec4 qd = s * dual;
  const float n = glm::length(qr);
  if (!(n > 1e-6f)) return a * (1.0f - t) + c * t;  // A whole turn: no way is shorter.
  qr /= n;
  qd /= n;
  const glm::vec3 translation = 2.0f * glm::vec3(quatMul(qd, glm::vec4(-glm::vec3(qr), qr.w)));
  glm::mat4 blended(rotationOf(qr) * (1.0f - t + t * scale));
  blended[3] = glm::vec4(translation, 1.0f);
  // What the delta holds beyond its rigid part and uniform scale, in proportion.
  glm::mat4 rigid(rotationOf(q) * scale);
  rigid[3] = glm::vec4(v, 1.0f);
  return (blended + (d - rigid) * t) * a;
}

}  // namespace si
