// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Layered animation's per-instance state: the overlay clip an instance plays on one of the
// crowd's joint masks, its weight fading between two values, and the layer record the frame
// builder writes from it (si::LayerRecord).

#include <algorithm>
#include <cstdint>

#include "crowd/playback.h"
#include "si/crowd/instance_record.h"

namespace si::detail {

struct OverlayState {
  Playback playback{0, LoopMode::kLoop, 1.0f, 0.0, 0.0};
  uint32_t mask = 0;
  float weight_from = 0.0f, weight_to = 0.0f;  // Fading from one to the other,
  double fade_start = 0.0, fade_duration = 0.0;  // over this span of the crowd clock.
  bool active = false;  // Played since the instance was added (stopped ones stay, at weight 0).
  // A blend (CrowdManager::playBlend; instance_blend.cpp): the overlay plays the pair's upper
  // clip and the instance its lower one, both re-anchored on a shared phase whenever the
  // parameter moves.
  bool blend = false;
  uint32_t space = 0;
  float parameter = 0.0f;
  float blend_speed = 1.0f;  // The instance's speed along the blend.
  double phase = 0.0;        // Cycles at phase_clock, in [0, 1) for looping clips.
  double phase_clock = 0.0;
  double cycles_per_second = 0.0;  // blend_speed / the blended period (0: a zero period).
};

/// A blend's phase (cycles) at crowd clock `clock`.
inline double blendPhase(const OverlayState& o, double clock) {
  return o.phase + (clock - o.phase_clock) * o.cycles_per_second;
}

/// The overlay's weight at crowd clock `clock`.
inline float overlayWeight(const OverlayState& o, double clock) {
  if (!(o.fade_duration > 0.0) || clock >= o.fade_start + o.fade_duration) return o.weight_to;
  const double u = std::clamp((clock - o.fade_start) / o.fade_duration, 0.0, 1.0);
  return float(double(o.weight_from) + (double(o.weight_to) - double(o.weight_from)) * u);
}

/// The layer record of `o` at `clock` (all zero, weight 0, when it is not active).
inline LayerRecord layerRecordOf(const OverlayState& o, const std::vector<ClipTiming>& clips,
                                 const BakedPalette& palette, double clock) {
  LayerRecord r;
  if (!o.active) return r;
  const ClipTiming& c = clips[o.playback.clip];
  const FrameSample fs = fastSample(c, palette.clips[o.playback.clip], localTime(o.playback, c, clock));
  const uint32_t stride = palette.layout.frame_stride_texels;
  r.frames[0] = c.first_texel + fs.frame * stride;
  r.frames[1] = c.first_texel + fs.next_frame * stride;
  r.fraction = packFraction(fs.fraction, fs.mode);
  r.weight_mask = packLayerWeight(overlayWeight(o, clock), o.mask);
  return r;
}

}  // namespace si::detail
