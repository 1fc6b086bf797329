// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The GPU-driven path's state per crowd of one character (CrowdManager::identity()): each crowd
// drawn by drawCrowdGpuCulled keeps its own uploaded state, views and motion history, so several
// crowds of one character (10 crowds of 1M: a crowd holds at most 2^20 instances) draw without
// re-uploading one another. The staging ring and the pre-skinned rings are the renderer's,
// shared by every crowd (ScratchBuffers).
#include <cstdint>
#include <memory>
#include <vector>

#include "gl/paths/gpu_culled_path.h"

namespace si::detail {

class GpuCulledCrowds {
 public:
  /// A crowd not drawn in this many draws of the character loses its state (a crowd destroyed
  /// or no longer drawn frees its buffers); its next draw uploads it whole again. At most
  /// kMaxCrowds are kept; past that the least recently drawn goes.
  static constexpr uint64_t kIdleDraws = 4096;
  static constexpr uint32_t kMaxCrowds = 16;

  /// The state of crowd `identity` (CrowdManager::identity()), made when new (evicting as
  /// above; context current). Never null. It becomes last().
  GpuCulledPath* find(uint64_t identity);
  /// The crowd state drawn last (readGpuSelection), or null before the first draw.
  const GpuCulledPath* last() const { return last_; }
  /// Each kept crowd's GPU memory, in the order the crowds were first drawn.
  void memory(std::vector<CrowdGpuMemory>* out) const;
  /// Every crowd's GL objects deleted (context current). Idempotent.
  void release();

 private:
  struct Crowd {
    uint64_t identity = 0, last_draw = 0;
    std::unique_ptr<GpuCulledPath> path;
  };
  std::vector<Crowd> crowds_;
  uint64_t draws_ = 0;
  GpuCulledPath* last_ = nullptr;
};

}  // namespace si::detail
