// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Blend spaces in the instance store (si/crowd/blend_space.h): the instance's clip plays the
// blend's first clip, its overlay the second on the space's mask and a 2D blend's third and
// fourth clips its extra layers, all started at the same phase of their cycles and advancing at
// their durations over the blended period, so they stay in step; each parameter change
// re-anchors them at the phase reached.
#include <algorithm>
#include <cmath>
#include <limits>

#include "crowd/instance_root_motion.h"
#include "crowd/instance_store.h"

namespace si::detail {

void InstanceStore::anchorBlend(uint32_t i, const BlendSpace& space, glm::vec2 parameter,
                                double phase, double clock) {
  OverlayState& o = overlays[i];
  parameter.x = std::clamp(parameter.x, space.positions.front(), space.positions.back());
  if (space.is2D())
    parameter.y = std::clamp(parameter.y, space.positions_y.front(), space.positions_y.back());
  const BlendPoint b = blendPoint(space, parameter.x, parameter.y);
  double seconds[kMaxBlendLayers] = {};
  for (uint32_t k = 0; k < b.count; ++k)
    seconds[k] = (*clip_timings)[space.clips[b.clips[k]]].duration;
  // 1D: blendPeriod's arithmetic; 2D: the durations weighted by the clips' shares.
  double period = space.is2D() ? 0.0 : blendPeriod(seconds[0], seconds[1], b.chain[1]);
  for (uint32_t k = 0; space.is2D() && k < b.count; ++k) period += double(b.shares[k]) * seconds[k];
  const double rate = period > 0.0 ? double(o.blend_speed) / period : 0.0;
  phase = cycleFraction(phase);
  // Each clip at its duration over the period, held within a float (a huge speed over clips of
  // very different lengths would pass it).
  const auto playbackOf = [&](uint32_t k) {
    const uint32_t clip = space.clips[b.clips[k]];
    const float speed =
        float(std::min(seconds[k] * rate, double(std::numeric_limits<float>::max())));
    return Playback{clip, palette->clips[clip].loop_mode, speed, clock, phase * seconds[k]};
  };
  // The instance's clip (a crossfade under way keeps fading from what it came from), the
  // overlay, and a 2D blend's other two clips as extra layers; a 1D blend's extra layers fade
  // out.
  playback[i] = playbackOf(0);
  o.playback = playbackOf(1);
  o.mask = space.mask;
  float targets[kExtraLayers] = {};
  for (uint32_t k = 0; k < kExtraLayers; ++k)
    if (2 + k < b.count) {
      o.extra[k].playback = playbackOf(2 + k);
      targets[k] = b.chain[2 + k];
    }
  if (o.fade_duration > 0.0 && clock < o.fade_start + o.fade_duration) {
    // Still fading: on from the weights reached towards the new ones, over the span left.
    const double end = o.fade_start + o.fade_duration;
    o.weight_from = overlayWeight(o, clock);
    for (uint32_t k = 0; k < kExtraLayers; ++k) o.extra[k].weight_from = extraWeight(o, k, clock);
    o.fade_start = clock;
    o.fade_duration = end - clock;
  } else {
    o.weight_from = b.chain[1];
    for (uint32_t k = 0; k < kExtraLayers; ++k) o.extra[k].weight_from = targets[k];
    o.fade_duration = 0.0;
  }
  o.weight_to = b.chain[1];
  for (uint32_t k = 0; k < kExtraLayers; ++k) o.extra[k].weight_to = targets[k];
  o.parameter = parameter.x;
  o.parameter_y = space.is2D() ? parameter.y : 0.0f;
  o.phase = phase;
  o.phase_clock = clock;
  o.cycles_per_second = rate;
  changed(i);
}

Status InstanceStore::playBlend(InstanceHandle h, const BlendSpace& space, uint32_t space_id,
                                glm::vec2 parameter, double blend_seconds, double phase,
                                float speed, double clock) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  const float from = restartOverlay(i, clock);
  OverlayState& o = overlays[i];
  o.blend = true;
  o.space = space_id;
  o.blend_speed = speed;
  if (blend_seconds > 0.0) {  // Crossfade into the blend: the clip and the overlay's weight.
    fade_from[i] = playback[i];
    fade_start[i] = clock;
    fade_duration[i] = blend_seconds;
    o.weight_from = from;
    o.fade_start = clock;
    o.fade_duration = blend_seconds;
  } else {
    fade_duration[i] = 0.0;
    o.fade_duration = 0.0;
  }
  events_new[i] = 1;
  anchorBlend(i, space, parameter, phase, clock);
  return Status::ok();
}

Status InstanceStore::setBlendParameter(InstanceHandle h, const std::vector<BlendSpace>& spaces,
                                        glm::vec2 parameter, double clock) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  const OverlayState& o = overlays[i];
  if (!o.blend)
    return {StatusCode::kInvalidArgument,
            "setBlendParameter: the instance plays no blend (playBlend)"};
  if (root_motion[i]) applyRootMotion(*palette, *clip_timings, clock, *this, i);
  anchorBlend(i, spaces[o.space], parameter, blendPhase(o, clock), clock);
  return Status::ok();
}

void InstanceStore::endBlend(uint32_t i, double seconds, double clock) {
  if (overlays[i].blend) fadeOverlayOut(i, seconds, clock);
}

}  // namespace si::detail
