// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The rotation of a 3x3 matrix by polar decomposition, and its scale along that rotation's axes:
// what si::decomposePose and si::applyLookAt read off a joint's (possibly blended) matrix.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace si::detail {

/// `a` = R * S with R a rotation (polar decomposition, Higham's iteration) and S's diagonal in
/// `scale` (its shear dropped); a mirroring `a` is decomposed with x negated (scale.x < 0).
/// False, outputs unspecified, for a singular or non-finite matrix.
bool polarRotationScale(const glm::dmat3& a, glm::dquat* rotation, glm::dvec3* scale);

}  // namespace si::detail
