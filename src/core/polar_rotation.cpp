// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "core/polar_rotation.h"

#include <algorithm>
#include <cmath>

namespace si::detail {

// R <- (R + R^-T) / 2 converges quadratically to the rotation from a matrix of positive
// determinant; S's diagonal is read off R^T a.
bool polarRotationScale(const glm::dmat3& a, glm::dquat* rotation, glm::dvec3* scale) {
  const double det = glm::determinant(a);
  if (!std::isfinite(det) || det == 0.0) return false;
  glm::dmat3 r = a;
  if (det < 0.0) r[0] = -r[0];
  for (int k = 0; k < 64; ++k) {
    const glm::dmat3 next = 0.5 * (r + glm::transpose(glm::inverse(r)));
    double change = 0.0;
    for (int c = 0; c < 3; ++c) change = std::max(change, glm::length(next[c] - r[c]));
    r = next;
    if (!(change > 1e-15)) break;  // A NaN stops too, and fails below.
  }
  const glm::dmat3 s = glm::transpose(r) * a;
  *scale = glm::dvec3(s[0][0], s[1][1], s[2][2]);
  *rotation = glm::normalize(glm::quat_cast(r));
  return std::isfinite(scale->x + scale->y + scale->z + rotation->w + rotation->x + rotation->y +
                       rotation->z);
}

}  // namespace si::detail
