// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// A look-at constraint on a pose of local joint transforms: a chain of joints (spine, neck,
/// head) turns so that a direction fixed in the character's bind pose points at a target, each
/// joint taking its share of the turn within its limit. It works on the CPU on any pose of
/// local transforms: an instance's pose as drawn (CrowdManager::localPose), or the engine's.
///
/// Usage (heads turning towards the camera):
/// \code
///   si::LookAt look;
///   look.chain = {{neck, 0.4, glm::radians(30.0)}, {head, 1.0, glm::radians(50.0)}};
///   look.forward = {0.0, 0.0, 1.0};                  // where the bind pose looks, model space
///   std::vector<si::TransformD> pose(skeleton.jointCount());
///   si::Status s = crowd.localPose(h, skeleton, pose);
///   if (s.isOk()) s = si::applyLookAt(skeleton, look, camera_in_model_space, pose);
///   if (s.isOk()) s = si::composePose(skeleton, pose, model, skinning);  // reference_evaluator.h
/// \endcode

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/skeleton.h"
#include "si/core/span.h"
#include "si/core/status.h"
#include "si/core/transform.h"

namespace si {

/// One joint of a look-at chain.
struct LookAtJoint {
  uint32_t joint = 0;  ///< Skeleton joint.
  /// The share, in (0, 1], of the turn still to make (from this joint's position, after the
  /// joints before it turned) that this joint takes: a chain's last joint usually takes 1.
  double share = 1.0;
  /// The most this joint turns away from its pose, radians, in [0, pi].
  double max_angle_radians = 3.141592653589793;
};

/// What turns and how far.
struct LookAt {
  /// Root-most first; each joint a descendant of the one before.
  std::vector<LookAtJoint> chain;
  /// The direction the character looks in its bind pose, in model space (not unit length
  /// needed; not zero). Each chain joint carries it as its bind pose does.
  glm::dvec3 forward = glm::dvec3(0.0, 0.0, 1.0);
  /// How much of each joint's (limited) turn is applied, in [0, 1]: 0 leaves the pose as it is,
  /// fading it in and out is a hand-over without a pop.
  double weight = 1.0;

  /// kInvalidArgument naming the first rule broken: an empty chain, a share outside (0, 1], a
  /// limit outside [0, pi], a weight outside [0, 1] (or any of them not finite), a zero or
  /// non-finite forward; kOutOfRange for a joint past the skeleton; kNotSorted for a joint that
  /// does not descend from the one before.
  Status validate(const Skeleton& skeleton) const;
};

/// Turns `local_pose` (one local transform per skeleton joint, the pose's model space that of
/// `target`) so that the chain looks at `target`: joint by joint, root-most first, the
/// joint's forward (`look.forward` carried from the bind pose into the joint's current frame)
/// is turned about the joint's position towards the target by share x the angle between
/// them, at most its limit, times the weight; its rotation alone changes, so its descendants
/// follow and every other joint keeps its transform. A joint at the target turns none.
/// Fails, leaving the pose unchanged, as look.validate() and the skeleton's validate() do,
/// with kCountMismatch for a pose of the wrong size, kNotFinite for a target that is not
/// finite or a pose whose matrices are.
Status applyLookAt(const Skeleton& skeleton, const LookAt& look, const glm::dvec3& target,
                   Span<TransformD> local_pose);

}  // namespace si
