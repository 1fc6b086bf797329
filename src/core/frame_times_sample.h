// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The end of si::sampleFrames() for a clip with frame times, shared with the crowd's own frame
// lookup (src/crowd/playback.h), which finds the frame through a finer table.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "si/core/baked_palette.h"

namespace si::detail {

/// For `clip` with frame times (frame_times_seconds.size() == frame_count >= 2) and `t` within
/// [0, duration]: the sample of sampleFrames(clip, t), given `after`, the index of the first
/// frame whose time is past t (frame_count when none; 0 reads as 1).
inline FrameSample frameTimesSample(const BakedClip& clip, double t, size_t after) {
  const std::vector<double>& times = clip.frame_times_seconds;
  const uint32_t i =
      static_cast<uint32_t>(std::min<size_t>(after == 0 ? 0 : after - 1, clip.frame_count - 2));
  const double span = times[i + 1] - times[i];
  FrameSample s;
  s.frame = i;
  s.next_frame = i + 1;
  s.fraction =
      span > 0.0 ? static_cast<float>(std::min(std::max((t - times[i]) / span, 0.0), 1.0)) : 1.0f;
  s.mode = intervalModeAt(clip, i);
  return s;
}

}  // namespace si::detail
