// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Frames placed at a clip's keys: between two keys every track interpolates smoothly, so the
// bake divides each key interval on its own, as finely as its own error asks.
#include <cstdint>
#include <vector>

#include "si/bake/bake_desc.h"

namespace si::detail {

/// planPalette() with each selected clip's frames given (`frames`, one per selected clip)
/// instead of planned from a rate; kCountMismatch when the counts differ.
Status planPaletteWithFrames(const Character& character, const BakeDesc& desc,
                             const std::vector<FramePlan>& frames,
                             Span<const FrameInterpolation> clip_interpolations, PalettePlan* out);

/// 0, every key time of every track strictly inside the clip (any interpolation), and the
/// duration: sorted, times closer than 1e-6 s merged. Just {0} for a zero-length clip.
std::vector<double> keyBreakpoints(const Clip& clip);

/// Frames at `breakpoints` (keyBreakpoints()), key interval i divided evenly into pieces[i]
/// (at least 1) frame intervals. A STEP key's time holds two frames, the pose just before it
/// and the pose at it (FramePlan::before_step), both breaks; with `cubic`, every breakpoint's
/// frame is a break too (the curve may turn there). frame_interval_seconds is the widest grid
/// spacing that divides the duration and is at least every gap, so sampleFrames() finds each
/// frame from its grid index. `pieces` must have breakpoints.size() - 1 entries.
FramePlan framesAtKeys(const Clip& clip, const std::vector<double>& breakpoints,
                       const std::vector<uint32_t>& pieces, bool cubic);

}  // namespace si::detail
