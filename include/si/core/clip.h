// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Animation clips: per-joint translation, rotation and scale keyframe tracks with glTF 2.0
/// interpolation semantics.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "si/core/morph_target.h"
#include "si/core/root_motion.h"
#include "si/core/status.h"
#include "si/core/transform.h"

namespace si {

/// How values between two keys are computed (glTF 2.0 `sampler.interpolation`).
enum class Interpolation : uint8_t {
  kDefault = 0,  ///< Resolved to kLinear, glTF's default.
  kLinear,       ///< Lerp for vectors, shortest-arc slerp for rotations.
  kStep,         ///< Holds the value of the key at or before the time.
  kCubicSpline,  ///< Hermite spline; values hold (in-tangent, value, out-tangent) per key and
                 ///< tangents are scaled by the key interval, as glTF specifies.
};

/// Returns kLinear for kDefault and `i` otherwise.
Interpolation resolveInterpolation(Interpolation i);
/// Returns "LINEAR", "STEP", "CUBICSPLINE" (or "DEFAULT").
const char* interpolationName(Interpolation i);

/// What happens when a clip plays past its duration.
enum class LoopMode : uint8_t {
  kDefault = 0,  ///< Resolved to kOnce.
  kOnce,         ///< Plays once and holds the pose at `duration_seconds`.
  kLoop,         ///< Wraps: time is taken modulo `duration_seconds`.
};

/// Returns kOnce for kDefault and `m` otherwise.
LoopMode resolveLoopMode(LoopMode m);

/// One animated property of one joint. For kLinear and kStep, `values` has one element per key;
/// for kCubicSpline three per key: in-tangent, value, out-tangent. An empty track leaves the
/// property at the skeleton's rest pose.
template <typename T>
struct Track {
  Interpolation interpolation = Interpolation::kDefault;
  std::vector<float> times_seconds;  ///< Strictly increasing, finite, not negative.
  std::vector<T> values;

  /// Number of keys.
  size_t keyCount() const { return times_seconds.size(); }
  /// True when the track animates nothing.
  bool empty() const { return times_seconds.empty(); }
};

using Vec3Track = Track<glm::vec3>;
using QuatTrack = Track<glm::quat>;

/// The three tracks of one joint.
struct JointTracks {
  Vec3Track translation;
  QuatTrack rotation;  ///< Keys need not be unit length; evaluation normalizes.
  Vec3Track scale;
};

/// The animated weights of `target_count` consecutive morph targets from `first_target` (a glTF
/// `weights` channel; SkinnedMesh::morph_targets). Each key holds target_count weights in target
/// order; for kCubicSpline three runs of target_count per key, as glTF lays them out:
/// in-tangents, weights, out-tangents. Sampled as joint tracks are (before the first key the
/// first holds, after the last the last, or towards the first with Clip::wrap_interpolates).
struct MorphWeightTrack {
  uint32_t first_target = 0;
  uint32_t target_count = 0;
  Interpolation interpolation = Interpolation::kDefault;
  std::vector<float> times_seconds;  ///< Strictly increasing, finite, not negative.
  std::vector<float> values;

  size_t keyCount() const { return times_seconds.size(); }
};

/// A named instant of a clip (a footstep, a hit): what animation events report when a
/// playback passes it (CrowdManager adds a palette's markers at init()).
struct AnimationMarker {
  double time_seconds = 0.0;  ///< Clip-local, within [0, duration].
  std::string name;           ///< Not empty.
  bool operator==(const AnimationMarker& o) const {
    return time_seconds == o.time_seconds && name == o.name;
  }
};

/// Checks `markers` of a clip of `duration` seconds: each time finite (kNotFinite) and within
/// [0, duration] (kOutOfRange), each name not empty (kInvalidArgument); `where` starts the
/// message.
Status validateMarkers(const std::vector<AnimationMarker>& markers, double duration,
                       const std::string& where);

/// One named animation of a skeleton. `joint_tracks` has one entry per skeleton joint.
struct Clip {
  std::string name;
  float duration_seconds = 0.0f;  ///< At least the last key time of every track; 0 allowed.
  LoopMode loop_mode = LoopMode::kDefault;
  /// Only for kLoop: when true, the span between a track's last key and the loop point
  /// interpolates towards the track's first key (as if that key were repeated at
  /// `duration_seconds + first key time`). When false (the default, glTF's convention that a
  /// cycle repeats its first key at the end) values after the last key hold it.
  bool wrap_interpolates = false;
  std::vector<JointTracks> joint_tracks;
  /// Morph target weights, at most one track per target; a target no track covers keeps its
  /// MorphTarget::default_weight.
  std::vector<MorphWeightTrack> morph_tracks;
  /// Named instants (animation events), in any order; the baker copies them to the BakedClip.
  std::vector<AnimationMarker> markers;
  /// Root motion (si/core/root_motion.h): when `extract` is set, the reference evaluator and so
  /// the baker give the clip's poses in place, and the baker keeps the motion
  /// (BakedClip::root_motion). Off by default.
  RootMotionSettings root_motion;

  /// The largest key time of all tracks, morph tracks included (0 for a clip without keys).
  float lastKeyTime() const;

  /// Checks against a skeleton of `joint_count` joints and a mesh of `morph_target_count` morph
  /// targets (by default any count up to kMaxMorphTargets) and reports the first rule broken;
  /// the message names the clip, joint or morph track and property:
  /// - joint_tracks.size() == joint_count (kCountMismatch);
  /// - duration_seconds finite and not negative (kNotFinite / kOutOfRange);
  /// - interpolation and loop mode are known enumerators (kInvalidArgument);
  /// - per track: key times finite (kNotFinite), not negative (kOutOfRange), strictly increasing
  ///   (kNotSorted), not after duration_seconds (kOutOfRange); values count equals the key count,
  ///   or three times it for kCubicSpline (kCountMismatch); values finite (kNotFinite); rotation
  ///   key values (not tangents) of non-zero length (kInvalidArgument);
  /// - morph tracks: at least one target each, none overlapping another (kInvalidArgument),
  ///   all below morph_target_count (kOutOfRange); keys as above, target_count values per key
  ///   (three runs of them for kCubicSpline);
  /// - markers as validateMarkers() says.
  Status validate(size_t joint_count, size_t morph_target_count = kMaxMorphTargets) const;
};

/// A clip that holds the skeleton's rest pose: no keys (every joint keeps its rest transform),
/// duration 0 (a palette bakes it as one frame), kOnce. For skinned assets without animation,
/// so a crowd of posed characters can be baked and drawn; si::importGltfFile adds one named
/// "rest_pose" when the file has no animation (GltfImportDesc::rest_pose_clip_when_none).
Clip makeRestPoseClip(size_t joint_count, const std::string& name = "rest_pose");

}  // namespace si
