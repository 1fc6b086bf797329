// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The end of si::sampleFrames() for a clip with frame times, shared with the crowd's own frame
// lookup (src/crowd/playback.h), which finds the frame through a finer table.
#include <cstddef>

#include "si/core/baked_palette.h"

namespace si::detail {

/// For `clip` with frame times (frame_times_seconds.size() == frame_count >= 2) and `t` within
/// [0, duration]: the sample of sampleFrames(clip, t), given `after`, the index of the first
/// frame whose time is past t (frame_count when none; 0 reads as 1).
FrameSample frameTimesSample(const BakedClip& clip, double t, size_t after);

}  // namespace si::detail
