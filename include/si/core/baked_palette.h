// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// A baked palette as data: the texture's texels, its layout, the clip table with frame times and
/// culling bounds, and the joint maps; plus the CPU emulation of what the vertex shader computes
/// from it. si::bake produces palettes (and measures them with this emulation); si::crowd plays
/// them; si::gl uploads them. docs/palette-format.md specifies the layout.

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "si/core/bounds.h"
#include "si/core/clip.h"
#include "si/core/palette_layout.h"
#include "si/core/skinned_mesh.h"
#include "si/core/span.h"
#include "si/core/status.h"

namespace si {

/// How each joint of each frame is stored in the palette texture.
enum class PaletteFormat : uint8_t {
  kDefault = 0,          ///< Resolved to kMatrix3x4F32.
  kMatrix3x4F32,         ///< Three RGBA32F texels: the rows of the 3x4 skinning matrix. Exact.
  kMatrix3x4F16,         ///< Three RGBA16F texels: half the memory, about 1e-3 relative error.
  kQuatTranslationF32,   ///< Two RGBA32F texels: unit rotation quaternion, then translation and
                         ///< uniform scale. Rigid joints only; interpolated on the rotation.
};

/// Returns kMatrix3x4F32 for kDefault and `f` otherwise.
PaletteFormat resolvePaletteFormat(PaletteFormat f);
/// "matrix3x4_f32", "matrix3x4_f16", "quat_translation_f32" (or "default").
const char* paletteFormatName(PaletteFormat f);
/// Data texels per joint: 3 for the matrix formats, 2 for kQuatTranslationF32.
uint32_t texelsPerJoint(PaletteFormat f);
/// Bytes per texel: 16 for F32 formats, 8 for kMatrix3x4F16.
uint32_t bytesPerTexel(PaletteFormat f);

/// How the shader interpolates a clip between its baked frames.
enum class FrameInterpolation : uint8_t {
  kLinear = 0,  ///< Two frames: rows lerped (the rotation format nlerps).
  kCubic = 1,   ///< Four frames: a uniform Catmull-Rom spline through the frames, per interval
                ///< as BakedClip::interval_modes says (the rotation format: the quaternion's
                ///< components, then normalized). Needs the layout's border frames.
};
/// "linear" or "cubic".
const char* frameInterpolationName(FrameInterpolation i);

/// What the shader does between frames i and i + 1 of a cubic clip (the frames at i - 1 and
/// i + 2 are read only where the curve is smooth through frames i and i + 1).
enum class IntervalMode : uint8_t {
  kLinear = 0,        ///< Frames i and i + 1 lerped (zero-length STEP spans, both ends broken).
  kCubic = 1,         ///< Catmull-Rom through frames i - 1, i, i + 1, i + 2.
  kCubicStartsHere = 2,  ///< Frame i starts the piece (a clip's start, a STEP key): frame
                         ///< i - 1 is replaced by the quadratic extrapolation 3 f(i) - 3 f(i + 1)
                         ///< + f(i + 2).
  kCubicEndsNext = 3,    ///< Frame i + 1 ends the piece: frame i + 2 is replaced by 3 f(i + 1)
                         ///< - 3 f(i) + f(i - 1).
};

/// One clip of a baked palette.
struct BakedClip {
  std::string name;
  LoopMode loop_mode = LoopMode::kOnce;
  float duration_seconds = 0.0f;
  double frame_interval_seconds = 0.0;  ///< Grid spacing; 0 for a single frame.
  uint32_t frame_count = 1;
  uint32_t first_texel = 0;             ///< Same as the layout's clip_first_texel.
  /// Empty when frames sit on the uniform grid; otherwise (STEP keys, frames placed at the
  /// keys) each frame's clip-local time (non-decreasing; a STEP key appears twice: the pose
  /// before it, then at it).
  std::vector<double> frame_times_seconds;
  FrameInterpolation interpolation = FrameInterpolation::kLinear;
  /// For a cubic clip, one IntervalMode value per frame interval (frame_count - 1; none for a
  /// single frame); empty for a linear clip.
  std::vector<uint8_t> interval_modes;
  std::vector<AnimationMarker> markers;  ///< The clip's markers (Clip::markers).
  /// Root motion (si/core/root_motion.h) of a clip baked in place (Clip::root_motion.extract):
  /// one sample per frame, M at the frame's time as (translation x, translation z, yaw), the
  /// first (0, 0, 0), consecutive yaws less than pi apart. Empty: the clip moves in its poses.
  std::vector<glm::vec3> root_motion;
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
  /// Per palette joint, a box in the bind pose holding every vertex weighted to it, each
  /// widened by the farthest its morph targets move it at the weights the palette's frames
  /// reach: what bounds a pose the engine gives (CrowdManager::setLivePose) for culling. Empty
  /// when unknown (a palette file before version 6): such poses are culled by their clip's
  /// sphere.
  std::vector<Aabb> joint_bounds;

  /// Index of the clip named `name`, or -1.
  int32_t findClip(const std::string& name) const;

  /// Checks every field against the others, as a freshly baked palette satisfies them, so that
  /// a palette from anywhere (a file, a cache, a network) is as safe to play and draw as a
  /// bake. Reports the first rule broken, naming the clip, frame, joint or texel:
  /// - format known; 1 to kMaxPaletteJoints palette joints, strictly increasing skeleton joints
  ///   below skeleton_to_palette.size() (at most 65536), which maps exactly them to their slots
  ///   and every other joint to -1 (kInvalidArgument);
  /// - 1 to kMaxPaletteClips clips; the layout equals the one computePaletteLayout() gives for
  ///   the clips' frame counts, the format's texels per joint and the stored joint stride (at
  ///   most 64), and each clip's first_texel is the layout's (kInvalidArgument);
  /// - texel_bytes holds exactly width x height texels of the format (kCountMismatch); every
  ///   texel value of a stored joint and of the morph target weights is finite (kNotFinite); in the
  ///   quaternion format each rotation is unit length within 1e-3 and each scale positive
  ///   (kOutOfRange);
  /// - each clip: loop mode kOnce or kLoop; duration finite, in [0, kMaxClipSeconds]; 1 to 2^21
  ///   frames; a single frame has interval 0, several have a positive interval that divides
  ///   the duration into a whole number of intervals (relative 1e-6) no greater than the frames
  ///   less one; frame times, when present, one per frame, non-decreasing, from 0 to the
  ///   duration, no gap wider than the interval, none repeated more than twice (a STEP key);
  ///   bounds finite, not empty, the sphere finite, centred within the box and at least as
  ///   large as half its diagonal (kOutOfRange);
  /// - interpolation known; a linear clip without interval modes, a cubic one with one known
  ///   mode per interval in a layout with border frames (kInvalidArgument, kCountMismatch,
  ///   kOutOfRange); border frames' texels obey the texel rules above;
  /// - markers as si::validateMarkers() says (times within [0, duration], names not empty);
  /// - root motion empty or one sample per frame, finite, the first (0, 0, 0), consecutive
  ///   yaws less than pi apart (kCountMismatch, kNotFinite, kOutOfRange);
  /// - character_height finite and >= 0 (kOutOfRange);
  /// - joint_bounds empty or one per palette joint (kCountMismatch), each finite, and either
  ///   empty (the Aabb default) or min <= max on every axis (kOutOfRange).
  Status validate() const;
};

/// Largest values BakedPalette::validate() accepts (and the palette file can hold).
inline constexpr uint32_t kMaxPaletteJoints = 65535;
inline constexpr uint32_t kMaxPaletteClips = 65536;
inline constexpr uint32_t kMaxClipFrames = uint32_t(1) << 21;
inline constexpr double kMaxClipSeconds = 1.0e6;

// ---------------------------------------------------------------------------------------------
// CPU emulation of the shader: the same addressing, decoding and interpolation in float.

/// Which baked frames a clip-local time uses, and the blend between them: what an instance
/// record carries to the GPU.
struct FrameSample {
  uint32_t frame = 0;       ///< Frame index within the clip.
  uint32_t next_frame = 0;  ///< frame + 1, or frame for a single-frame clip.
  float fraction = 0.0f;    ///< Blend towards next_frame, in [0, 1].
  IntervalMode mode = IntervalMode::kLinear;  ///< The clip's interval mode (linear clips: kLinear).
};

/// The mode of interval `interval` in a clip's `modes` (BakedClip::interval_modes): kLinear
/// for an interval past them (a linear clip has none) or a value that is not a mode.
inline IntervalMode intervalModeAt(const std::vector<uint8_t>& modes, uint32_t interval) {
  return interval < modes.size() && modes[interval] <= 3u ? static_cast<IntervalMode>(modes[interval])
                                                          : IntervalMode::kLinear;
}
/// The mode of interval `interval` of `clip` (intervalModeAt(clip.interval_modes, interval)).
inline IntervalMode intervalModeAt(const BakedClip& clip, uint32_t interval) {
  return intervalModeAt(clip.interval_modes, interval);
}

/// The fraction word of an InstanceRecord (blend.x or blend.y): the float bits of `fraction`
/// (in [0, 1], where bits 30 and 31 are 0) with the interval mode in bits 30-31.
inline uint32_t packFraction(float fraction, IntervalMode mode) {
  uint32_t bits;
  std::memcpy(&bits, &fraction, 4);
  return (bits & 0x3FFFFFFFu) | (uint32_t(mode) & 3u) << 30;
}
/// The inverse of packFraction(): the fraction (bits 30-31 cleared) and the mode.
float unpackFraction(uint32_t word, IntervalMode* mode);

/// Frame sample for clip-local time `local_time_seconds` (clamped to [0, duration], NaN read
/// as 0; any clip, valid or not, gives frames within its frame count): constant
/// time on the uniform grid, a binary search over frame_times_seconds for clips with frame
/// times (STEP keys, frames at keys; at a STEP key time exactly, the frame after the jump).
FrameSample sampleFrames(const BakedClip& clip, double local_time_seconds);

/// For a clip with STEP keys (frame_times_seconds), per grid interval i the frame index its
/// search may start from: every frame in [i, table[i]) lies at or before any time of interval
/// i. Empty for uniform clips. With it, sampleFrames() finds a frame in a step or two.
std::vector<uint32_t> frameSearchStarts(const BakedClip& clip);
/// sampleFrames() with the search started from `search_starts` (frameSearchStarts(clip), or
/// empty for the binary search): the same result. Another table of that size still gives
/// frames within the clip, not necessarily the same ones.
FrameSample sampleFrames(const BakedClip& clip, double local_time_seconds,
                         Span<const uint32_t> search_starts);

/// The interval modes a cubic clip gets from its frame times (frame_times_seconds, or the uniform
/// grid when empty): kCubic where frames i - 1 to i + 2 lie evenly spaced (within 1 %) and no
/// frame in `breaks` (a frame where the curve has a corner or jump: both frames of a STEP key)
/// lies at i or i + 1; kCubicStartsHere / kCubicEndsNext where only one side is missing; kLinear
/// where both are or the interval has zero length. `wraps`: the clip loops seamlessly, so the
/// border frames continue it (frame -1 = frame n - 2, frame n = frame 1) and its ends need no
/// extrapolation. `breaks` holds one flag per frame, or is empty.
std::vector<uint8_t> cubicIntervalModes(const BakedClip& clip, bool wraps,
                                        Span<const uint8_t> breaks);

/// Decodes palette joint `slot` of frame `frame` of clip `clip` as a 3x4 matrix (returned as a
/// mat4 with last row 0 0 0 1), exactly as the shader reads it. Arguments must be in range.
glm::mat4 decodeJoint(const BakedPalette& palette, uint32_t clip, uint32_t frame, uint32_t slot);

/// The skinning matrix of palette slot `slot` the shader computes for `sample` of `clip`:
/// matrices lerped row by row, or for kQuatTranslationF32 the rotation nlerped (shorter arc),
/// translation and scale lerped, then composed; cubic modes use the Catmull-Rom weights on the
/// same values (quaternions aligned to frame i's hemisphere, then normalized). Float
/// arithmetic, like the GPU.
glm::mat4 emulateSkinningMatrix(const BakedPalette& palette, uint32_t clip,
                                const FrameSample& sample, uint32_t slot);

/// The same for a frame pair given by texel offsets, as an InstanceRecord carries them
/// (clip first texel + frame * frame stride): what the shader computes for palette slot `slot`
/// with `fraction` between the two frames. Offsets must lie inside the palette.
glm::mat4 emulateFrameMatrix(const BakedPalette& palette, uint32_t frame_texel,
                             uint32_t next_frame_texel, float fraction, uint32_t slot);
/// The same with an interval mode: for the cubic modes the frames one frame stride before
/// `frame_texel` and after `next_frame_texel` (for next == frame, all four are the one frame),
/// which must lie inside the palette (border frames).
glm::mat4 emulateFrameMatrix(const BakedPalette& palette, uint32_t frame_texel,
                             uint32_t next_frame_texel, float fraction, IntervalMode mode,
                             uint32_t slot);

/// The morph target weights the shader computes for a frame pair given by texel offsets (as
/// emulateFrameMatrix() takes them): each target's stored weight lerped by `fraction`, or for
/// the cubic modes blended with the Catmull-Rom weights over the four frames. `out` holds one
/// weight per stored target (layout.morph_target_count; kCountMismatch otherwise); the offsets
/// must lie inside the palette.
Status emulateMorphWeights(const BakedPalette& palette, uint32_t frame_texel,
                           uint32_t next_frame_texel, float fraction, IntervalMode mode,
                           Span<float> out);

/// Skinning matrices of every skeleton joint (identity for joints not stored) for `sample`.
/// `out` must hold skeleton_to_palette.size() matrices (kCountMismatch otherwise).
Status emulateSkinningMatrices(const BakedPalette& palette, uint32_t clip,
                               const FrameSample& sample, Span<glm::mat4> out);

/// Skins `mesh` (bound to the skeleton the palette was baked from) with `matrices` from
/// emulateSkinningMatrices() in float, as the vertex shader does: its morph targets added at
/// `morph_weights` (emulateMorphWeights(); empty: each target's default weight), the normal
/// renormalized; then the matrices of its influences blended by weight (zero weights skipped),
/// the position transformed by the blend and the normal by sign(det) * cofactor of its 3x3,
/// normalized. `out_normals` may be empty. kCountMismatch for wrong sizes, and as
/// si::validateMorphTargets() for targets that do not validate.
Status emulateSkinning(const SkinnedMesh& mesh, Span<const glm::mat4> matrices,
                       Span<glm::vec3> out_positions, Span<glm::vec3> out_normals,
                       Span<const float> morph_weights = {});

/// Converts a float to IEEE half (round to nearest even; overflow to infinity) and back.
uint16_t floatToHalf(float value);
float halfToFloat(uint16_t half);

}  // namespace si
