// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// What to bake: palette format, sample rate and clip selection, and how frames are placed.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/core/palette_layout.h"

namespace si {

/// How each clip's sample rate is chosen.
enum class RateMode : uint8_t {
  kDefault = 0,  ///< Resolved to kAutomatic.
  kFixed,        ///< Every clip at BakeDesc::sample_rate_hz.
  kAutomatic,    ///< Per clip, the fewest frames whose measured max error is at most
                 ///< error_tolerance_ratio * character height: on a uniform grid (the lowest
                 ///< candidate rate) or placed at the clip's keys with each key interval
                 ///< divided for its own error, whichever has fewer. A clip that cannot meet
                 ///< it fails the bake with kToleranceNotMet (BakeDesc::accept_tolerance_miss).
};

/// How clips interpolate between their baked frames (si::FrameInterpolation per clip).
enum class InterpolationChoice : uint8_t {
  kDefault = 0,  ///< Resolved to kLinear.
  kLinear,       ///< Every clip linear: two frames per read.
  kCubic,        ///< Every clip cubic (Catmull-Rom through the frames, four frames per read).
  kSmaller,      ///< With kAutomatic rates: per clip, the one that meets the tolerance (when
                 ///< only one does), then the one with fewer frames, then the smaller error;
                 ///< with kFixed rates, kCubic.
};
/// "linear", "cubic", "smaller" (or "default").
const char* interpolationChoiceName(InterpolationChoice c);

/// Where the automatic mode may place a clip's frames.
enum class FramePlacement : uint8_t {
  kDefault = 0,  ///< Resolved to kFewer.
  kFewer,        ///< Per clip, whichever of kGrid and kKeys meets the tolerance with fewer frames.
  kGrid,         ///< A uniform grid at one of the candidate rates (a frame follows from the time
                 ///< alone; keys off the grid have their corners cut).
  kKeys,         ///< A frame at every key of every track, each key interval divided evenly for
                 ///< its own error (up to 4 x max_sample_rate_hz within it).
};
/// "fewer", "grid", "keys" (or "default").
const char* framePlacementName(FramePlacement p);

/// Where bakePalette() stands, for a progress bar.
struct BakeProgress {
  double fraction = 0.0;       ///< 0 at the start, 1 when done; never decreases.
  const char* stage = "";      ///< "choosing rates", "baking" or "measuring".
  uint32_t clip = 0;           ///< The clip being worked on (palette order),
  uint32_t clip_count = 0;     ///< of this many.
};

/// Bake options. Zero fields take the defaults documented on each.
struct BakeDesc {
  PaletteFormat format = PaletteFormat::kDefault;
  RateMode rate_mode = RateMode::kDefault;
  /// Linear (default), cubic, or per clip whichever is smaller. Any cubic clip gives the
  /// palette border frames (two more frames per clip: the loop's continuation, or copies of
  /// the end frames).
  InterpolationChoice interpolation = InterpolationChoice::kDefault;
  /// For kAutomatic: where frames may sit (kFewer by default). kFixed always uses a grid.
  FramePlacement placement = FramePlacement::kDefault;
  /// Frames per second of every clip for kFixed (and unselected clips' figure in the report's
  /// bytes_saved); 0 means 30.
  float sample_rate_hz = 0.0f;
  /// For kAutomatic: the tolerance as a fraction of the character's height; 0 means 1e-4.
  /// The default bake (kAutomatic) keeps every clip's max error within it where the format
  /// allows (the report says per clip whether it did).
  float error_tolerance_ratio = 0.0f;
  /// For kAutomatic: the highest rate tried on a uniform grid; 0 means 240. Frames placed at a
  /// clip's keys may reach 4 times it within the key intervals that need it.
  float max_sample_rate_hz = 0.0f;
  /// For kAutomatic: keep a bake that misses the tolerance (the report says where) instead of
  /// failing with kToleranceNotMet.
  bool accept_tolerance_miss = false;
  /// Shell metric distance as a fraction of the character's height; 0 means 0.05.
  float shell_distance_ratio = 0.0f;
  /// Names of the clips to bake, in palette order; empty means all clips of the character.
  std::vector<std::string> clip_names;
  /// Texel stride between joints; 0 means texelsPerJoint rounded up to a power of two.
  uint32_t joint_stride_texels = 0;
  /// GL_MAX_TEXTURE_SIZE of the target; 0 means 16384.
  uint32_t max_texture_size = 0;
  /// Largest palette texture the bake may make, in bytes; 0 means 512 MiB. A bake past it (a
  /// hostile clip's duration, an absurd rate) fails with kLimitExceeded naming the figure
  /// before anything is allocated or evaluated; the automatic mode checks every trial too.
  uint64_t max_palette_bytes = 0;
  /// Largest amount of evaluation the bake may do, counted as frames x (skeleton joints +
  /// drawn vertices) summed over the baked clips (each automatic-rate trial counts on its
  /// own); 0 means 2^33, about a minute of one core. A bake past it fails with kLimitExceeded
  /// naming the figure before evaluating anything: a small palette can still hide a huge
  /// skeleton or mesh.
  uint64_t max_evaluations = 0;
  /// Called on the baking thread at each clip of each stage and once with fraction 1 at the
  /// end; may be empty. It must not throw.
  std::function<void(const BakeProgress&)> progress;
};

/// Returns the desc with zeros replaced by their documented defaults (clip_names untouched).
BakeDesc resolveDefaults(const BakeDesc& desc);

/// Frames baked for a clip of `duration_seconds` at (at least) `rate_hz`, and their spacing:
/// n = ceil(duration * rate) intervals of dt = duration / n, so frames sit at 0, dt, ..., duration
/// (n + 1 frames) and the last one lies exactly on the clip's end. For a looping clip the last
/// frame holds the pose at the end approached from the left (see evaluateLocalPose()), so the
/// shader interpolates frame i into frame i + 1 for every clip and never wraps; the last frame
/// equals the first for a seamless glTF loop and differs where the clip holds its last key
/// (Clip::wrap_interpolates false). A zero-length clip gets one frame.
struct FramePlan {
  uint32_t frame_count = 1;
  double frame_interval_seconds = 0.0;  ///< 0 for a single frame.
  /// Empty for the uniform grid above. For a clip with STEP keys, or frames placed at its keys
  /// (FramePlacement::kKeys): the time of every frame, non-decreasing. Each STEP key time k inside the clip holds two frames, the pose just
  /// before k and the pose at k (grid frames within 1e-6 intervals of k are replaced), so a
  /// hold never blends and the other channels keep interpolating.
  std::vector<double> frame_times_seconds;
  /// With frame_times_seconds: 1 for a frame holding the pose just before its time.
  std::vector<uint8_t> before_step;
  /// Empty, or one flag per frame: 1 where the curve may break (both frames of a STEP key; a
  /// corner key with planClipFrames()'s breaks_at_corners).
  std::vector<uint8_t> breaks;
};
FramePlan planFrames(double duration_seconds, double rate_hz);

/// planFrames() plus the STEP key frames of `clip` (see FramePlan::frame_times_seconds). With
/// `breaks_at_corners` (cubic clips), also every cornerKeyTimes() time: a frame within 1e-3
/// intervals of it is marked as a break, otherwise a frame is added at it and marked. A cubic
/// interval never reads across a break (si::cubicIntervalModes()). A plan of more than 2^20
/// frames (what planPalette refuses) holds its count alone: no frame times, no breaks.
FramePlan planClipFrames(const Clip& clip, double rate_hz, bool breaks_at_corners = false);

/// Times inside the clip (0 < t < duration) where its curve may have a corner: the keys of
/// every LINEAR track (lerp and slerp change slope at each key). Sorted, without repeats.
std::vector<double> cornerKeyTimes(const Clip& clip);

/// The rate of the grid that holds every corner key of `clip` and its end (keys sampled at 24
/// or 30 Hz, as exporters write them): 1 / the shortest spacing between corner keys when
/// every corner key and the duration are whole multiples of it (within 1e-3 of it); 0 when
/// there are none or they are not on such a grid. Cubic automatic rates try its multiples.
double cornerKeyRate(const Clip& clip);

/// The clips a desc selects (indices into character.clips), the joints the palette stores and
/// the palette layout a bake will produce, without evaluating anything. Only joints that some
/// vertex of some sub-mesh LOD is weighted to are stored ("model only what the scene needs");
/// their ancestors still shape them through the reference evaluation. `clip_rates_hz`, when not
/// empty, gives each selected clip its own rate (the baker's automatic mode) instead of
/// desc.sample_rate_hz; `clip_interpolations`, when not empty, each its interpolation instead
/// of desc.interpolation's (kSmaller plans cubic). Fails with kInvalidArgument for a rate that is not finite and positive,
/// an unknown format, rate mode or interpolation, a character without clips, a rates or
/// interpolations span of the wrong size;
/// kNotFound naming a clip that does not exist; kLimitExceeded when more than 2^20 frames per
/// clip are asked for, when the texture would take more than max_palette_bytes or the bake more
/// than max_evaluations, or from computePaletteLayout(). `out` is untouched on failure.
struct PalettePlan {
  std::vector<uint32_t> clip_indices;
  std::vector<FramePlan> frames;         ///< One per selected clip.
  std::vector<FrameInterpolation> interpolations;  ///< One per selected clip.
  std::vector<uint32_t> palette_joints;  ///< Skeleton joints stored, in skeleton order.
  PaletteLayout layout;
  uint64_t texture_bytes = 0;            ///< width * height * bytesPerTexel.
};
Status planPalette(const Character& character, const BakeDesc& desc, PalettePlan* out,
                   Span<const double> clip_rates_hz = {},
                   Span<const FrameInterpolation> clip_interpolations = {});

/// Vertices referenced by some LOD of some sub-mesh (what is ever drawn), ascending. Index
/// ranges and indices outside the mesh are ignored.
std::vector<uint32_t> drawnVertices(const SkinnedMesh& mesh);

/// Skeleton joints that some drawn vertex (drawnVertices()) has a non-zero weight on, in
/// skeleton order. The mesh must be valid for the skeleton.
std::vector<uint32_t> usedJoints(const Character& character);

}  // namespace si
