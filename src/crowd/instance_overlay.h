// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Layered animation's per-instance state: the overlay clip an instance plays on one of the
// crowd's joint masks, its weight fading between two values, and the layer record the frame
// builder writes from it (si::LayerRecord).

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "crowd/playback.h"
#include "si/crowd/instance_record.h"

namespace si::detail {

/// A 2D blend's third and fourth clips (instance_blend.cpp): layers composed after the overlay on
/// its mask, their weights fading over the overlay's span.
struct ExtraLayer {
  Playback playback{0, LoopMode::kLoop, 1.0f, 0.0, 0.0};
  float weight_from = 0.0f, weight_to = 0.0f;
};

/// Layers an instance draws beyond its overlay, at most (a 2D blend's).
inline constexpr uint32_t kExtraLayers = 2;

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
  float parameter_y = 0.0f;  // A 2D space's second parameter.
  ExtraLayer extra[kExtraLayers];
  float blend_speed = 1.0f;  // The instance's speed along the blend.
  double phase = 0.0;        // Cycles at phase_clock, in [0, 1) for looping clips.
  double phase_clock = 0.0;
  double cycles_per_second = 0.0;  // blend_speed / the blended period (0: a zero period).
};

/// A phase's place in its cycle, in [0, 1); 0 where the cycles are past what a double resolves
/// (not finite: a clock near the largest double times the cycles a second).
inline double cycleFraction(double phase) {
  if (phase >= 1.0 || phase < 0.0) phase -= std::floor(phase);  // Cycles repeat.
  return phase >= 0.0 && phase < 1.0 ? phase : 0.0;
}

/// A blend's phase (cycles) at crowd clock `clock`.
inline double blendPhase(const OverlayState& o, double clock) {
  return o.phase + (clock - o.phase_clock) * o.cycles_per_second;
}

/// A weight fading from `from` to `to` over the overlay's span, at crowd clock `clock`.
inline float fadedWeight(const OverlayState& o, float from, float to, double clock) {
  if (!(o.fade_duration > 0.0) || clock >= o.fade_start + o.fade_duration) return to;
  const double u = std::clamp((clock - o.fade_start) / o.fade_duration, 0.0, 1.0);
  return float(double(from) + (double(to) - double(from)) * u);
}

/// The overlay's weight at crowd clock `clock`.
inline float overlayWeight(const OverlayState& o, double clock) {
  return fadedWeight(o, o.weight_from, o.weight_to, clock);
}

/// Extra layer `k`'s weight at crowd clock `clock`.
inline float extraWeight(const OverlayState& o, uint32_t k, double clock) {
  return fadedWeight(o, o.extra[k].weight_from, o.extra[k].weight_to, clock);
}

/// Every layer's weight held where it is at `clock`, before the fade span changes.
inline void holdExtraWeights(OverlayState& o, double clock) {
  for (uint32_t k = 0; k < kExtraLayers; ++k)
    o.extra[k].weight_from = o.extra[k].weight_to = extraWeight(o, k, clock);
}

/// The layer record of `playback` at weight `weight` on mask `mask`.
inline LayerRecord layerRecordAt(const Playback& playback, float weight, uint32_t mask,
                                 const std::vector<ClipTiming>& clips, const BakedPalette& palette,
                                 double clock) {
  LayerRecord r;
  const ClipTiming& c = clips[playback.clip];
  const FrameSample fs = fastSample(c, palette.clips[playback.clip], localTime(playback, c, clock));
  const uint32_t stride = palette.layout.frame_stride_texels;
  r.frames[0] = c.first_texel + fs.frame * stride;
  r.frames[1] = c.first_texel + fs.next_frame * stride;
  r.fraction = packFraction(fs.fraction, fs.mode);
  r.weight_mask = packLayerWeight(weight, mask);
  return r;
}

/// The layer record of `o` at `clock` (all zero, weight 0, when it is not active).
inline LayerRecord layerRecordOf(const OverlayState& o, const std::vector<ClipTiming>& clips,
                                 const BakedPalette& palette, double clock) {
  if (!o.active) return LayerRecord{};
  return layerRecordAt(o.playback, overlayWeight(o, clock), o.mask, clips, palette, clock);
}

/// The layer record of `o` at `clock`; unless `extras` is null, its kExtraLayerRecords extra ones
/// into `extras` (zero where a layer's weight is 0) and kLayerExtrasBit set on it when any is
/// drawn.
inline LayerRecord layerRecordsOf(const OverlayState& o, const std::vector<ClipTiming>& clips,
                                  const BakedPalette& palette, double clock, LayerRecord* extras) {
  static_assert(kExtraLayers == kExtraLayerRecords, "a record per extra layer");
  LayerRecord r = layerRecordOf(o, clips, palette, clock);
  for (uint32_t k = 0; extras != nullptr && k < kExtraLayers; ++k) {
    const float w = o.active ? extraWeight(o, k, clock) : 0.0f;
    const LayerRecord e = w > 0.0f
                              ? layerRecordAt(o.extra[k].playback, w, o.mask, clips, palette, clock)
                              : LayerRecord{};
    if ((e.weight_mask & 0xFFFFu) != 0) r.weight_mask |= kLayerExtrasBit;
    extras[k] = e;
  }
  return r;
}

}  // namespace si::detail
