// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Root motion: a clip's travel over the ground, taken out of its poses so it can be baked in
/// place and applied to the instance instead (no foot sliding when the application moves the
/// character; or playback speed matched to the application's own movement).
///
/// Model space is +Y up (glTF). A clip marked with Clip::root_motion.extract has a root joint
/// (RootMotionSettings::joint); its *ground frame* at clip-local time t is the joint's position
/// dropped onto the ground plane (x, z) and turned by the joint's yaw (its rotation's twist
/// about +Y). The clip's root motion M(t) is the ground frame at t relative to the one at 0: a
/// GroundMotion. The reference evaluator (evaluatePose) then returns M(t)^-1 * pose(t), the
/// pose in place; the baker bakes that and stores M at every frame (BakedClip::root_motion);
/// the crowd moves instances that opt in by M(t0)^-1 * M(t1) over each update.
///
/// Usage:
/// \code
///   character.clips[walk].root_motion.extract = true;     // before si::bakePalette
///   ...
///   si::GroundMotion per_cycle = si::rootMotionAt(palette.clips[walk], palette.clips[walk]
///                                                 .duration_seconds);
///   si::RootMotionSummary v = si::summarizeRootMotion(palette.clips[walk]);  // units/s, rad/s
///   instance_desc.root_motion = true;                     // CrowdManager applies it
/// \endcode

#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "si/core/status.h"

namespace si {

struct BakedClip;
struct Clip;
enum class LoopMode : uint8_t;  // si/core/clip.h
struct FrameSample;
struct Skeleton;

/// Per clip: whether its root motion is taken out of its poses (Clip::root_motion).
struct RootMotionSettings {
  bool extract = false;  ///< Bake the clip in place and keep its motion (BakedClip::root_motion).
  /// The joint whose ground travel and yaw are the motion (typically the hips). Empty: the
  /// first joint, in skeleton order, with a translation track in the clip; failing that, the
  /// first with a rotation track; failing that, joint 0.
  std::string joint;
};

/// A rigid motion over the ground plane: turn by `yaw` radians about +Y, then move by
/// (translation.x, 0, translation.y). As a matrix: T(x, 0, z) * R_y(yaw).
struct GroundMotion {
  glm::dvec2 translation = glm::dvec2(0.0);  ///< (x, z), model units.
  double yaw = 0.0;                          ///< Radians about +Y; not wrapped (a clip's
                                             ///< samples are continuous, so yaw can pass pi).
};

/// `radians` wrapped into (-pi, pi]: the shorter way between two yaws is wrapAngle(b - a).
double wrapAngle(double radians);

/// The 4x4 matrix T(x, 0, z) * R_y(yaw).
glm::dmat4 groundMotionMatrix(const GroundMotion& m);
/// `a` then `b` in `a`'s frame: the motion whose matrix is matrix(a) * matrix(b).
GroundMotion composeGroundMotion(const GroundMotion& a, const GroundMotion& b);
/// The motion whose matrix is matrix(m)^-1.
GroundMotion inverseGroundMotion(const GroundMotion& m);
/// `m` composed with itself `count` times (identity for 0), by repeated squaring.
GroundMotion repeatGroundMotion(const GroundMotion& m, uint64_t count);

/// The skeleton joint clip `clip`'s root motion is taken from (RootMotionSettings::joint).
/// kNotFound naming the joint when no skeleton joint has that name. Whether the clip extracts
/// at all is not checked. The skeleton and clip must be valid.
Status rootMotionJoint(const Skeleton& skeleton, const Clip& clip, uint32_t* joint);

/// M(t): the ground frame of the root joint at clip-local time `local_time_seconds` (clamped to
/// [0, duration]; a loop's duration gives the pose approached from the left, as
/// evaluateLocalPose() does) relative to the one at 0, evaluated in double from the clip's
/// tracks (the motion itself, whether or not the clip extracts it). The yaw is in (-pi, pi].
/// Fails as evaluatePose() does, and as rootMotionJoint().
Status evaluateRootMotion(const Skeleton& skeleton, const Clip& clip, double local_time_seconds,
                          GroundMotion* out);

/// The baked root motion of `clip` at `sample` (its frames' samples lerped, yaw included).
/// Identity for a clip without root motion.
GroundMotion sampleRootMotion(const BakedClip& clip, const FrameSample& sample);
/// The same at clip-local time `local_time_seconds` (through si::sampleFrames).
GroundMotion rootMotionAt(const BakedClip& clip, double local_time_seconds);

/// The baked motion of a playback of `clip` (with `loop`: kLoop or kOnce) from unwrapped clip
/// time `from_seconds` to `to_seconds` (start time + elapsed time x speed, before wrapping):
/// M(from)^-1 * M(to), with one whole cycle M(duration) for every loop boundary crossed (at
/// most 2^20 per call; more are not counted). Identity for a clip without root motion, or
/// when either time is not finite.
GroundMotion rootMotionBetween(const BakedClip& clip, LoopMode loop, double from_seconds,
                               double to_seconds);

/// What a clip's root motion amounts to per second, from its baked samples.
struct RootMotionSummary {
  GroundMotion whole_clip;  ///< M(duration): one cycle of a loop, or the whole travel.
  /// whole_clip's translation and yaw divided by the duration (0 for a zero-length clip):
  /// units per second (in the clip's starting frame) and radians per second.
  glm::dvec2 average_velocity = glm::dvec2(0.0);
  double average_yaw_rate = 0.0;
  double average_speed = 0.0;  ///< |average_velocity|.
};
RootMotionSummary summarizeRootMotion(const BakedClip& clip);

}  // namespace si
