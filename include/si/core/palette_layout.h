// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Where each clip, frame and joint of a baked palette lives in the palette texture. This is the
/// one definition of the addressing that the baker, the CPU emulation of the shader and the
/// GLSL code share (docs/palette-format.md describes it like a file format).
///
/// The palette is a 2D RGBA texture `width` texels wide (a power of two). Texels are numbered
/// row by row: linear index i sits at x = i & (width - 1), y = i >> log2(width). Clip c starts at
/// texel `clip_first_texel[c]`; frame f of it at `+ f * frame_stride_texels`; joint j of that
/// frame at `+ j * joint_stride_texels`, whose first `texels_per_joint` texels hold the joint's
/// data (three matrix rows, or rotation and translation).

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/span.h"
#include "si/core/status.h"

namespace si {

/// Inputs of computePaletteLayout().
struct PaletteLayoutDesc {
  uint32_t joint_count = 0;  ///< Joints stored per frame; at least 1.
  /// Frames of each clip, in palette order; at least one clip, each with at least one frame.
  Span<const uint32_t> clip_frame_counts;
  uint32_t texels_per_joint = 0;  ///< Data texels per joint, 1 to 4 (3 for 3x4 matrices).
  /// Texels from one joint to the next: 0 means the default, texels_per_joint rounded up to a
  /// power of two (so a joint never straddles a texture row); otherwise at least
  /// texels_per_joint.
  uint32_t joint_stride_texels = 0;
  /// Largest width or height allowed (GL_MAX_TEXTURE_SIZE); 0 means 16384.
  uint32_t max_texture_size = 0;
  /// 0, or 1 to store a border frame before and after every clip (cubic interpolation reads
  /// them): clip c's frames then start one frame stride after its region starts.
  uint32_t border_frames = 0;
  /// Morph target weights stored per frame (SkinnedMesh::morph_targets), 0 to
  /// kMaxMorphTargets: four to a texel after the joints, the frame padded to whole joint
  /// strides.
  uint32_t morph_target_count = 0;
};

/// Returns the desc with zeros replaced by their documented defaults.
PaletteLayoutDesc resolveDefaults(const PaletteLayoutDesc& desc);

/// Result of computePaletteLayout().
struct PaletteLayout {
  uint32_t width = 0;       ///< Power of two.
  uint32_t width_log2 = 0;  ///< log2(width).
  uint32_t height = 0;
  uint32_t joint_count = 0;
  uint32_t texels_per_joint = 0;
  uint32_t joint_stride_texels = 0;
  /// joint_count * joint_stride_texels, plus the morph weights' texels rounded up to whole
  /// joint strides.
  uint32_t frame_stride_texels = 0;
  uint32_t morph_target_count = 0;
  /// Where a frame's morph weights start, from the frame's first texel:
  /// joint_count * joint_stride_texels.
  uint32_t morph_first_texel = 0;
  uint32_t border_frames = 0;               ///< Per clip end (0 or 1).
  std::vector<uint32_t> clip_first_texel;   ///< One per clip.
  std::vector<uint32_t> clip_frame_count;   ///< One per clip.
  uint64_t used_texel_count = 0;            ///< Texels holding data or padding between joints.

  /// First texel of frame `frame` of clip `clip`, where `frame` may also name a border frame
  /// (-border_frames to clip_frame_count[clip] - 1 + border_frames; asserted in debug builds).
  uint32_t frameTexel(uint32_t clip, int64_t frame) const;
  /// Linear texel index of clip `clip`, frame `frame`, joint `joint`, data texel `row`.
  /// Arguments must be in range (asserted in debug builds).
  uint32_t texelIndex(uint32_t clip, uint32_t frame, uint32_t joint, uint32_t row) const;
  /// Linear texel index of the weights of morph targets 4 * (target / 4) to 4 * (target / 4) + 3
  /// in clip `clip`, frame `frame` (which may name a border frame, as for frameTexel()).
  uint32_t morphTexel(uint32_t clip, int64_t frame, uint32_t target) const {
    return frameTexel(clip, frame) + morph_first_texel + target / 4u;
  }
  /// Texture coordinate (x, y) of linear texel `index`.
  glm::uvec2 texelCoord(uint32_t index) const {
    return glm::uvec2(index & (width - 1u), index >> width_log2);
  }
  /// Total texels of the texture (width * height).
  uint64_t textureTexelCount() const { return uint64_t(width) * height; }
};

/// Lays out the palette: frames of clip 0 first (after its border frame, when there are
/// border frames; clip_first_texel is frame 0's), then clip 1, and so on; the texture is as
/// close to square as a power-of-two width allows, so both sizes stay small. Fails, leaving
/// `out` untouched, with kInvalidArgument for a null `out`, zero joints, no clips, a clip with
/// no frames, border_frames above 1, texels_per_joint outside 1..4 or a stride below it, a
/// max_texture_size that is not a power of two, more than kMaxMorphTargets morph targets;
/// kLimitExceeded (naming the sizes) when the palette does not fit in a max_texture_size square
/// texture or needs more than 2^32 texels.
Status computePaletteLayout(const PaletteLayoutDesc& desc, PaletteLayout* out);

}  // namespace si
