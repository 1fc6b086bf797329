// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The traditional baseline: per visible instance, its joint matrices (and morph target
// weights) computed on the CPU from the palette, uploaded into a uniform block, and one
// glDrawElements per worn sub-mesh.

#include <vector>

#include "gl/paths/draw_path.h"
#include "gl/paths/live_palette.h"
#include "si/core/morph_target.h"

namespace si::detail {

/// Joints the traditional path's uniform block holds: 48 KiB of rows.
inline constexpr uint32_t kMaxTraditionalJoints = 1024;
/// Morph target weights it holds, before the joint rows of a character that has targets
/// (skinned.vert.glsl's SI_TRADITIONAL_MORPH_TARGETS): every target a palette may have, 1 KiB.
inline constexpr uint32_t kTraditionalMorphTargets = uint32_t(kMaxMorphTargets);

class TraditionalPath final : public DrawPath {
 public:
  Status prepare(const DrawResources& r) override;
  /// kLimitExceeded when the palette stores more joints than the block holds.
  Status draw(const DrawResources& r, const PathFrame& frame, DrawStats* stats) override;
  void release() override;
  uint64_t gpuBytes() const;  ///< Its joint block's buffer.

 private:
  GLuint block_buffer_ = kNoObject;
  std::vector<uint8_t> block_;
  std::vector<float> morph_weights_;
  LivePalette live_palette_;  // The palette with the crowd's live poses, when it has room.
};

}  // namespace si::detail
