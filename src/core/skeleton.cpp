// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/skeleton.h"

#include "core/str_cat.h"

namespace si {
using detail::strCat;

int32_t Skeleton::findJoint(std::string_view name) const {
  for (size_t i = 0; i < joint_names.size(); ++i)
    if (joint_names[i] == name) return static_cast<int32_t>(i);
  return -1;
}

Status Skeleton::validate() const {
  const size_t n = parents.size();
  if (n == 0) return {StatusCode::kLimitExceeded, "skeleton: needs at least one joint"};
  if (n > kMaxJoints)
    return {StatusCode::kLimitExceeded,
            strCat("skeleton: ", n, " joints exceed the maximum of ", kMaxJoints)};
  if (joint_names.size() != n)
    return {StatusCode::kCountMismatch, strCat("skeleton: joint_names has ", joint_names.size(),
                                               " elements, parents has ", n)};
  if (rest_pose.size() != n)
    return {StatusCode::kCountMismatch,
            strCat("skeleton: rest_pose has ", rest_pose.size(), " elements, parents has ", n)};
  if (inverse_bind_matrices.size() != n)
    return {StatusCode::kCountMismatch,
            strCat("skeleton: inverse_bind_matrices has ", inverse_bind_matrices.size(),
                   " elements, parents has ", n)};
  for (size_t i = 0; i < n; ++i) {
    const auto name = [&] { return strCat("skeleton: joint ", i, " '", joint_names[i], "': "); };
    if (parents[i] < kNoParent)
      return {StatusCode::kOutOfRange, name() + strCat("parent ", parents[i], " is invalid")};
    if (parents[i] >= static_cast<int32_t>(i))
      return {StatusCode::kNotSorted,
              name() + strCat("parent ", parents[i], " must precede the joint (parents first)")};
    const Transform& t = rest_pose[i];
    if (!isFinite(t.translation) || !isFinite(t.rotation) || !isFinite(t.scale))
      return {StatusCode::kNotFinite, name() + "rest pose is not finite"};
    if (glm::dot(t.rotation, t.rotation) == 0.0f)
      return {StatusCode::kInvalidArgument, name() + "rest rotation has zero length"};
    if (!isFinite(inverse_bind_matrices[i]))
      return {StatusCode::kNotFinite, name() + "inverse bind matrix is not finite"};
  }
  return Status::ok();
}

}  // namespace si
