// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::bake: the AnimationBaker. Evaluates every frame of every selected clip on the CPU and
/// stores each joint's skinning matrix (joint * inverse bind) in one palette texture that the
/// vertex shader reads with texelFetch; measures what the shader will compute against the
/// double-precision reference and reports the error; computes per-clip culling bounds.
///
/// Usage:
/// \code
///   si::Character character;
///   si::makeDefaultCharacter({}, &character);
///   si::BakeDesc desc;                       // float32 3x4 matrices, 30 Hz, every clip
///   si::BakedPalette palette;
///   si::BakeReport report;
///   si::Status s = si::bakePalette(character, desc, &palette, &report);
///   // palette.texel_bytes -> a width x height RGBA32F texture;
///   // report.clips[c].max_error_units: the largest vertex displacement of clip c.
/// \endcode
///
/// The palette types (BakedPalette, BakedClip) and the CPU emulation of the shader
/// (sampleFrames, emulateSkinning, ...) live in si/core/baked_palette.h.

#include <cstdint>
#include <string>
#include <vector>

#include "si/bake/bake_desc.h"
#include "si/core/baked_palette.h"
#include "si/core/character.h"

namespace si {

/// Error of one clip, measured over many times (each frame interval at fractions 0, 1/4, 1/2,
/// 3/4, and the clip's end) by emulating the shader and comparing with the reference evaluator
/// in double.
struct ClipErrorReport {
  std::string name;
  FrameInterpolation interpolation = FrameInterpolation::kLinear;
  double sample_rate_hz = 0.0;
  uint32_t frame_count = 0;
  /// Bytes of this clip's frames, border frames included (data and joint padding).
  uint64_t palette_bytes = 0;
  double max_error_units = 0.0;     ///< Largest vertex displacement, model units.
  double p99_error_units = 0.0;     ///< 99th percentile over every (time, vertex) sample.
  double mean_error_units = 0.0;
  double max_error_ratio = 0.0;     ///< max_error_units / character height.
  double p99_error_ratio = 0.0;
  double mean_error_ratio = 0.0;
  double max_error_time_seconds = 0.0;  ///< Where the max occurred: clip-local time,
  uint32_t max_error_vertex = 0;        ///< vertex index,
  uint32_t max_error_joint = 0;         ///< and the vertex's largest-weight skeleton joint.
  /// ACL-style shell metric: virtual vertices at shell_distance along +-X, +-Y, +-Z of each
  /// stored joint, rigidly bound to it; the largest displacement of any of them.
  double shell_max_error_units = 0.0;
  double shell_distance_units = 0.0;
  /// Whether max_error_ratio <= BakeDesc::error_tolerance_ratio (in every rate mode).
  bool tolerance_met = true;
  /// Frames placed at the clip's keys, each key interval divided for its own error (automatic
  /// mode); sample_rate_hz is then the average, (frame_count - 1) / duration.
  bool frames_at_keys = false;
  uint64_t samples = 0;       ///< (time, vertex) pairs measured.
  /// Root motion (Clip::root_motion.extract; empty and 0 otherwise): the joint it was taken
  /// from, and the largest error of the baked motion (BakedClip::root_motion lerped between
  /// frames, si::rootMotionAt) against the reference's (si::evaluateRootMotion) at the same
  /// times: translation error + yaw error x character height (a bound on how far any point
  /// within a height of the root is misplaced), in units and as a fraction of the height. The
  /// figures above measure the in-place poses.
  std::string root_motion_joint;
  double root_motion_max_error_units = 0.0;
  double root_motion_max_error_ratio = 0.0;
};

/// What a bake produced and what it left out.
struct BakeReport {
  std::vector<ClipErrorReport> clips;
  double max_error_units = 0.0;  ///< Over all clips.
  double max_error_ratio = 0.0;
  double p99_error_units = 0.0;  ///< Largest per-clip P99.
  uint64_t palette_bytes = 0;    ///< The texture (width * height * bytes per texel).
  std::vector<std::string> joints_left_out;  ///< Joints no vertex is weighted to.
  std::vector<std::string> clips_left_out;   ///< Clips not selected.
  /// Texel bytes a bake of every joint and every clip (unselected clips at
  /// BakeDesc::sample_rate_hz) would have used, minus the texel bytes this bake uses.
  uint64_t bytes_saved = 0;
};

/// Bakes `character` per `desc` into `palette` and measures it into `report` (may be null to
/// skip the measurement, except that automatic rates always measure). Validates the character
/// and the desc first (the codes of Character::validate() and planPalette()); fails with
/// kUnsupported naming the clip, joint and time when kQuatTranslationF32 meets a joint with
/// non-uniform or negative scale; kLimitExceeded when the palette does not fit in the texture.
/// Outputs are untouched on failure.
///
/// A mesh with morph targets (SkinnedMesh::morph_targets) gets their weights in every frame
/// (palette-format.md, "Morph target weights"), sampled at the frame's time like the joints;
/// the measured error is the vertices' with the targets, so frame placement and the automatic
/// rate account for them.
Status bakePalette(const Character& character, const BakeDesc& desc, BakedPalette* palette,
                   BakeReport* report);

}  // namespace si
