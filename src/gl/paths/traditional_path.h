// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The traditional baseline: per visible instance, its joint matrices computed on the CPU from
// the palette, uploaded into a uniform block, and one glDrawElements per worn sub-mesh.

#include <vector>

#include "gl/paths/draw_path.h"

namespace si::detail {

/// Joints the traditional path's uniform block holds: 48 KiB of rows, within any 64 KiB block.
inline constexpr uint32_t kMaxTraditionalJoints = 1024;

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
};

}  // namespace si::detail
