// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The joint hierarchy a skinned mesh is bound to.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "si/core/status.h"
#include "si/core/transform.h"

namespace si {

/// A joint hierarchy in structure-of-arrays form. Joint `i` has `joint_names[i]`, `parents[i]`,
/// `rest_pose[i]` (its local transform when no clip animates it) and `inverse_bind_matrices[i]`
/// (model space to the joint's bind space). Editable input: fill the arrays, then validate().
struct Skeleton {
  /// Parent index of a root joint.
  static constexpr int32_t kNoParent = -1;
  /// Most joints a skeleton may have (vertex joint indices are 16-bit).
  static constexpr size_t kMaxJoints = 65535;

  std::vector<std::string> joint_names;  ///< May be empty strings; need not be unique.
  std::vector<int32_t> parents;          ///< kNoParent or an index below the joint's own.
  std::vector<Transform> rest_pose;      ///< Local transforms (parent space).
  std::vector<glm::mat4> inverse_bind_matrices;  ///< Identity when the source has none.

  /// Number of joints (the size of `parents`).
  size_t jointCount() const { return parents.size(); }

  /// Index of the first joint named `name`, or -1.
  int32_t findJoint(std::string_view name) const;

  /// Checks, in this order, and reports the first rule broken:
  /// - at least one joint, at most kMaxJoints (kLimitExceeded);
  /// - joint_names, rest_pose and inverse_bind_matrices have as many elements as parents
  ///   (kCountMismatch);
  /// - each parent is kNoParent or below the joint's index, so parents precede children
  ///   (kNotSorted), and not below kNoParent (kOutOfRange);
  /// - rest translations, rotations, scales and inverse bind matrices are finite (kNotFinite);
  /// - rest rotations have non-zero length (kInvalidArgument).
  Status validate() const;
};

}  // namespace si
