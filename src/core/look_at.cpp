// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/look_at.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "core/polar_rotation.h"
#include "core/str_cat.h"
#include "si/core/reference_evaluator.h"

namespace si {
using detail::strCat;

namespace {
constexpr double kPi = 3.141592653589793;

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x + v.y + v.z);
}

// A unit vector perpendicular to unit `f`.
glm::dvec3 perpendicular(const glm::dvec3& f) {
  const glm::dvec3 other = std::abs(f.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  return glm::normalize(glm::cross(f, other));
}
}  // namespace

Status LookAt::validate(const Skeleton& skeleton) const {
  if (chain.empty()) return {StatusCode::kInvalidArgument, "LookAt: the chain is empty"};
  if (!(weight >= 0.0 && weight <= 1.0))
    return {StatusCode::kInvalidArgument, strCat("LookAt: weight ", weight, " is not in [0, 1]")};
  if (!finite(forward) || glm::length(forward) == 0.0)
    return {StatusCode::kInvalidArgument, "LookAt: forward is zero or not finite"};
  const size_t n = skeleton.jointCount();
  for (size_t k = 0; k < chain.size(); ++k) {
    const LookAtJoint& c = chain[k];
    if (c.joint >= n)
      return {StatusCode::kOutOfRange, strCat("LookAt: chain[", k, "] joint ", c.joint,
                                              " is past the skeleton's ", n, " joints")};
    if (!(c.share > 0.0 && c.share <= 1.0))
      return {StatusCode::kInvalidArgument,
              strCat("LookAt: chain[", k, "] share ", c.share, " is not in (0, 1]")};
    if (!(c.max_angle_radians >= 0.0 && c.max_angle_radians <= kPi))
      return {StatusCode::kInvalidArgument, strCat("LookAt: chain[", k, "] max_angle_radians ",
                                                   c.max_angle_radians, " is not in [0, pi]")};
    if (k == 0) continue;
    const int32_t previous = int32_t(chain[k - 1].joint);
    int32_t p = skeleton.parents[c.joint];
    while (p != Skeleton::kNoParent && p != previous) p = skeleton.parents[size_t(p)];
    if (p != previous)
      return {StatusCode::kNotSorted,
              strCat("LookAt: chain[", k, "] joint ", c.joint, " does not descend from chain[",
                     k - 1, "] joint ", previous)};
  }
  return Status::ok();
}

Status applyLookAt(const Skeleton& skeleton, const LookAt& look, const glm::dvec3& target,
                   Span<TransformD> local_pose) {
  Status s = skeleton.validate();
  if (s.isOk()) s = look.validate(skeleton);
  if (!s.isOk()) return s;
  const size_t n = skeleton.jointCount();
  if (local_pose.size() != n)
    return {StatusCode::kCountMismatch, strCat("applyLookAt: the pose holds ", local_pose.size(),
                                               " transforms, the skeleton has ", n, " joints")};
  if (!finite(target)) return {StatusCode::kNotFinite, "applyLookAt: the target is not finite"};
  if (look.weight == 0.0) return Status::ok();
  // A copy, so that a failure leaves the caller's pose as it was.
  std::vector<TransformD> pose(local_pose.begin(), local_pose.end());
  std::vector<glm::dmat4> model(n), skinning(n);
  for (const LookAtJoint& c : look.chain) {
    s = composePose(skeleton, pose, model, skinning);
    if (!s.isOk()) return s;
    const glm::dmat4& m = model[c.joint];
    // The bind pose's forward in the joint's own frame, then in the model as the joint is now.
    const glm::dvec3 axis =
        glm::dmat3(glm::dmat4(skeleton.inverse_bind_matrices[c.joint])) * look.forward;
    glm::dvec3 f = glm::dmat3(m) * axis;
    glm::dvec3 to = target - glm::dvec3(m[3]);
    const double f_length = glm::length(f), to_length = glm::length(to);
    if (!std::isfinite(f_length + to_length) || f_length == 0.0)
      return {StatusCode::kNotFinite,
              strCat("applyLookAt: joint ", c.joint, "'s matrix is singular or not finite")};
    if (to_length <= 1e-12 * std::max(1.0, glm::length(target))) continue;  // At the target.
    f /= f_length;
    to /= to_length;
    const double angle = std::acos(std::clamp(glm::dot(f, to), -1.0, 1.0));
    glm::dvec3 about = glm::cross(f, to);
    const double about_length = glm::length(about);
    if (about_length < 1e-12) {
      if (angle < 0.5 * kPi) continue;  // Looking at it already.
      about = perpendicular(f);         // Straight behind: any side will do.
    } else {
      about /= about_length;
    }
    const double turn = std::min(c.share * angle, c.max_angle_radians) * look.weight;
    const glm::dmat3 q = glm::mat3_cast(glm::angleAxis(turn, about));
    // The turn about the joint's position in the model, in its parent's frame: the rotation
    // P^-1 Q P R (a rotation for a parent without shear; its polar rotation otherwise).
    const int32_t parent = skeleton.parents[c.joint];
    const glm::dmat3 p =
        parent == Skeleton::kNoParent ? glm::dmat3(1.0) : glm::dmat3(model[size_t(parent)]);
    const glm::dmat3 r = glm::mat3_cast(safeNormalize(pose[c.joint].rotation));
    glm::dvec3 unused_scale;
    if (!detail::polarRotationScale(glm::inverse(p) * q * p * r, &pose[c.joint].rotation,
                                    &unused_scale))
      return {StatusCode::kNotFinite,
              strCat("applyLookAt: joint ", parent, "'s matrix is singular or not finite")};
  }
  std::copy(pose.begin(), pose.end(), local_pose.begin());
  return Status::ok();
}

}  // namespace si
