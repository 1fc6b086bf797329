// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// What to bake: palette format, sample rate and clip selection, and how frames are placed.

#include <cstdint>
#include <string>
#include <vector>

#include "si/core/character.h"
#include "si/core/palette_layout.h"

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

/// Bake options. Zero fields take the defaults documented on each.
struct BakeDesc {
  PaletteFormat format = PaletteFormat::kDefault;
  /// Frames per second of every clip; 0 means 30.
  float sample_rate_hz = 0.0f;
  /// Names of the clips to bake, in palette order; empty means all clips of the character.
  std::vector<std::string> clip_names;
  /// Texel stride between joints; 0 means texelsPerJoint rounded up to a power of two.
  uint32_t joint_stride_texels = 0;
  /// GL_MAX_TEXTURE_SIZE of the target; 0 means 16384.
  uint32_t max_texture_size = 0;
};

/// Returns the desc with zeros replaced by their documented defaults (clip_names untouched).
BakeDesc resolveDefaults(const BakeDesc& desc);

/// Frames baked for a clip of `duration_seconds` at `rate_hz`, and their spacing. A clip that
/// plays once gets frames at 0, dt, ..., duration (the last exactly on its end), with
/// n = ceil(duration * rate) + 1 frames and dt = duration / (n - 1). A looping clip gets
/// n = ceil(duration * rate) frames at 0, dt, ..., duration - dt with dt = duration / n: its last
/// frame interpolates into its first. A zero-length clip gets one frame.
struct FramePlan {
  uint32_t frame_count = 1;
  double frame_interval_seconds = 0.0;  ///< 0 for a single frame.
};
FramePlan planFrames(double duration_seconds, double rate_hz, LoopMode loop_mode);

/// The clips a desc selects (indices into character.clips) and the palette layout a bake will
/// produce, without evaluating anything. Fails with kInvalidArgument for a rate that is not
/// finite and positive, or an unknown format; kNotFound naming a clip that does not exist;
/// kLimitExceeded when more than 2^20 frames per clip are asked for, or from
/// computePaletteLayout().
struct PalettePlan {
  std::vector<uint32_t> clip_indices;
  std::vector<FramePlan> frames;  ///< One per selected clip.
  PaletteLayout layout;
  uint64_t texture_bytes = 0;     ///< width * height * bytesPerTexel.
};
Status planPalette(const Character& character, const BakeDesc& desc, PalettePlan* out);

}  // namespace si
