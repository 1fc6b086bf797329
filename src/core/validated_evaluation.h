// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The reference evaluator without its checks, for callers that validated the skeleton and the
// clip once and evaluate them at many times (the baker: thousands of frames of a clip with
// thousands of keys, where checking every key at every time made baking quadratic).
#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"

namespace si::detail {

/// evaluateLocalPose() for a skeleton and clip that passed Skeleton::validate() and
/// Clip::validate(): the same result, without checking them again.
Status evaluateValidatedLocalPose(const Skeleton& skeleton, const Clip& clip,
                                  double local_time_seconds, ReferencePose* pose);
/// evaluateMorphWeights() likewise, for a clip that passed Clip::validate() against the mesh's
/// morph target count.
void evaluateValidatedMorphWeights(const SkinnedMesh& mesh, const Clip& clip,
                                   double local_time_seconds, Span<double> out);
/// evaluateRootMotion() likewise.
Status evaluateValidatedRootMotion(const Skeleton& skeleton, const Clip& clip,
                                   double local_time_seconds, GroundMotion* out);

}  // namespace si::detail
