// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "bake/border_frames.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace si::detail {

namespace {
// Bytes of one frame of `clip` at frame index `frame` (which may be -1 or n: a border frame).
uint8_t* frameBytes(BakedPalette* p, uint32_t clip, int64_t frame) {
  return p->texel_bytes.data() +
         size_t(p->layout.frameTexel(clip, frame)) * bytesPerTexel(p->format);
}
}  // namespace

bool wrapsSeamlessly(const BakedPalette& p, uint32_t clip) {
  const BakedClip& c = p.clips[clip];
  if (c.loop_mode != LoopMode::kLoop || c.frame_count < 3 || !c.frame_times_seconds.empty())
    return false;
  const PaletteLayout& l = p.layout;
  float largest = 0.0f, difference = 0.0f;
  for (uint32_t j = 0; j < l.joint_count; ++j) {
    const glm::mat4 a = decodeJoint(p, clip, 0, j), b = decodeJoint(p, clip, c.frame_count - 1, j);
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 3; ++row) {
        largest = std::max(largest, std::fabs(a[col][row]));
        difference = std::max(difference, std::fabs(a[col][row] - b[col][row]));
      }
  }
  if (l.morph_target_count > 0) {  // The weights close the loop too.
    std::vector<float> first(l.morph_target_count), last(l.morph_target_count);
    const uint32_t a = l.frameTexel(clip, 0), b = l.frameTexel(clip, c.frame_count - 1);
    if (!emulateMorphWeights(p, a, a, 0.0f, IntervalMode::kLinear, first).isOk() ||
        !emulateMorphWeights(p, b, b, 0.0f, IntervalMode::kLinear, last).isOk())
      return false;
    for (size_t k = 0; k < first.size(); ++k) {
      largest = std::max(largest, std::fabs(first[k]));
      difference = std::max(difference, std::fabs(first[k] - last[k]));
    }
  }
  return difference <= 1e-6f * std::max(largest, 1.0f);
}

void finishClipFrames(BakedPalette* p, uint32_t clip, FrameInterpolation interpolation,
                      const std::vector<uint8_t>& breaks) {
  BakedClip& c = p->clips[clip];
  c.interpolation = interpolation;
  c.interval_modes.clear();
  const bool wraps = wrapsSeamlessly(*p, clip);
  if (p->layout.border_frames == 1) {
    const size_t bytes = size_t(p->layout.frame_stride_texels) * bytesPerTexel(p->format);
    const int64_t n = c.frame_count;
    std::memcpy(frameBytes(p, clip, -1), frameBytes(p, clip, wraps ? n - 2 : 0), bytes);
    std::memcpy(frameBytes(p, clip, n), frameBytes(p, clip, wraps ? 1 : n - 1), bytes);
  }
  if (interpolation == FrameInterpolation::kCubic)
    c.interval_modes = cubicIntervalModes(c, wraps, breaks);
}

}  // namespace si::detail
