// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Cubic clips in a bake: whether a loop continues across its wrap, the border frames around
// each clip and the clip's interval modes.
#include <cstdint>
#include <vector>

#include "si/bake/bake_desc.h"
#include "si/core/baked_palette.h"

namespace si::detail {

/// Whether clip `clip` of `p` (already holding its frames) loops seamlessly on a uniform grid:
/// loop mode kLoop, at least 3 frames, and the last frame's texels (joints and morph weights)
/// equal the first's within 1e-6 of the largest magnitude. Then its border frames continue the
/// loop.
bool wrapsSeamlessly(const BakedPalette& p, uint32_t clip);

/// Writes clip `clip`'s border frames (the layout must have them): frames n - 2 and 1 of a
/// clip that wraps, copies of its first and last frames otherwise. Then sets its interpolation
/// and, for kCubic, its interval modes (cubicIntervalModes() with `breaks`, FramePlan::breaks).
void finishClipFrames(BakedPalette* p, uint32_t clip, FrameInterpolation interpolation,
                      const std::vector<uint8_t>& breaks);

}  // namespace si::detail
