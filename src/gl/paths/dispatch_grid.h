// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Compute dispatches past GL_MAX_COMPUTE_WORK_GROUP_COUNT's x (65535 is all GL guarantees: a
// pass of one thread per vertex or instance reaches it at 65535 x 64 = 4,194,240): the groups
// are laid out as rows of at most max_x, and the shaders index the flat group
// y * gl_NumWorkGroups.x + x (shaders/dispatch_index.glsl), skipping past the last thread.
// No GL here: the CPU side of every dispatch, testable without a GPU.

#include <algorithm>
#include <cstdint>

namespace si::detail {

struct DispatchGrid {
  uint32_t x = 0, y = 0;
};

/// A GL_MAX_COMPUTE_WORK_GROUP_COUNT limit as the passes use it: zero counts as GL's minimum.
inline uint32_t groupLimit(uint32_t limit) {
  return limit == 0 ? 65535u : limit;
}

/// The grid of `groups` groups in rows of at most `max_x`, at most `max_y` rows (a zero limit
/// counts as GL's minimum, 65535). False, `out` untouched, when they do not fit: the caller
/// refuses the dispatch by name (kLimitExceeded), never issues one past the limit.
inline bool dispatchGrid(uint64_t groups, uint32_t max_x, uint32_t max_y, DispatchGrid* out) {
  const uint64_t mx = groupLimit(max_x), my = groupLimit(max_y);
  const uint64_t x = std::min<uint64_t>(std::max<uint64_t>(groups, 1), mx);
  const uint64_t y = (std::max<uint64_t>(groups, 1) + x - 1) / x;
  if (y > my) return false;
  out->x = uint32_t(x);
  out->y = uint32_t(y);
  return true;
}

}  // namespace si::detail
