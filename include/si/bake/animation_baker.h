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

#include <cstdint>
#include <string>
#include <vector>

#include "si/bake/bake_desc.h"
#include "si/core/bounds.h"
#include "si/core/character.h"
#include "si/core/palette_layout.h"

namespace si {

/// One clip of a baked palette.
struct BakedClip {
  std::string name;
  LoopMode loop_mode = LoopMode::kOnce;
  float duration_seconds = 0.0f;
  double frame_interval_seconds = 0.0;  ///< Grid spacing; 0 for a single frame.
  uint32_t frame_count = 1;
  uint32_t first_texel = 0;             ///< Same as the layout's clip_first_texel.
  /// Empty when frames sit on the uniform grid; otherwise each frame's clip-local time
  /// (non-decreasing; a STEP key appears twice: the pose before it, then at it).
  std::vector<double> frame_times_seconds;
  Aabb bounds;                          ///< Conservative box of the skinned mesh over the clip.
  Sphere bounding_sphere;               ///< Conservative sphere, centred on the box.

  /// Effective sample rate (frames per second), 0 for a single frame.
  double sampleRateHz() const {
    return frame_interval_seconds > 0.0 ? 1.0 / frame_interval_seconds : 0.0;
  }
};

/// The palette texture and how to address it. Move-only in spirit (large); copying is allowed.
struct BakedPalette {
  PaletteFormat format = PaletteFormat::kMatrix3x4F32;
  PaletteLayout layout;
  std::vector<BakedClip> clips;
  /// Skeleton joint of each palette joint slot (joints no vertex is weighted to are left out).
  std::vector<uint32_t> palette_joints;
  /// Palette slot of each skeleton joint, or -1 when it is not stored.
  std::vector<int32_t> skeleton_to_palette;
  /// width * height texels of bytesPerTexel(format) bytes, row by row: RGBA32F or RGBA16F.
  std::vector<uint8_t> texel_bytes;
  float character_height = 0.0f;  ///< The unit of the relative error figures.

  /// Index of the clip named `name`, or -1.
  int32_t findClip(const std::string& name) const;
};

/// Error of one clip, measured over many times (each frame interval at fractions 0, 1/4, 1/2,
/// 3/4, and the clip's end) by emulating the shader and comparing with the reference evaluator
/// in double.
struct ClipErrorReport {
  std::string name;
  double sample_rate_hz = 0.0;
  uint32_t frame_count = 0;
  uint64_t palette_bytes = 0;       ///< Bytes of this clip's frames (data and joint padding).
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
  uint64_t samples = 0;       ///< (time, vertex) pairs measured.
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
Status bakePalette(const Character& character, const BakeDesc& desc, BakedPalette* palette,
                   BakeReport* report);

// ---------------------------------------------------------------------------------------------
// CPU emulation of the shader: the same addressing, decoding and interpolation in float.

/// Which baked frames a clip-local time uses, and the blend between them: what an instance
/// record carries to the GPU.
struct FrameSample {
  uint32_t frame = 0;       ///< Frame index within the clip.
  uint32_t next_frame = 0;  ///< frame + 1, or frame for a single-frame clip.
  float fraction = 0.0f;    ///< Blend towards next_frame, in [0, 1].
};

/// Frame sample for clip-local time `local_time_seconds` (clamped to [0, duration]): constant
/// time on the uniform grid, a binary search over frame_times_seconds for clips with STEP keys
/// (at a key time exactly, the frame after the jump).
FrameSample sampleFrames(const BakedClip& clip, double local_time_seconds);

/// Decodes palette joint `slot` of frame `frame` of clip `clip` as a 3x4 matrix (returned as a
/// mat4 with last row 0 0 0 1), exactly as the shader reads it. Arguments must be in range.
glm::mat4 decodeJoint(const BakedPalette& palette, uint32_t clip, uint32_t frame, uint32_t slot);

/// The skinning matrix of palette slot `slot` the shader computes for `sample` of `clip`:
/// matrices lerped row by row, or for kQuatTranslationF32 the rotation nlerped (shorter arc),
/// translation and scale lerped, then composed. Float arithmetic, like the GPU.
glm::mat4 emulateSkinningMatrix(const BakedPalette& palette, uint32_t clip,
                                const FrameSample& sample, uint32_t slot);

/// Skinning matrices of every skeleton joint (identity for joints not stored) for `sample`.
/// `out` must hold skeleton_to_palette.size() matrices (kCountMismatch otherwise).
Status emulateSkinningMatrices(const BakedPalette& palette, uint32_t clip,
                               const FrameSample& sample, Span<glm::mat4> out);

/// Skins `mesh` (bound to the skeleton the palette was baked from) with `matrices` from
/// emulateSkinningMatrices() in float, as the vertex shader does: up to 4 influences, zero
/// weights skipped; normals through sign(det) * cofactor, normalized. `out_normals` may be
/// empty. kCountMismatch for wrong sizes.
Status emulateSkinning(const SkinnedMesh& mesh, Span<const glm::mat4> matrices,
                       Span<glm::vec3> out_positions, Span<glm::vec3> out_normals);

/// Converts a float to IEEE half (round to nearest even; overflow to infinity) and back.
uint16_t floatToHalf(float value);
float halfToFloat(uint16_t half);

}  // namespace si
