// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Blend spaces in the instance store (si/crowd/blend_space.h): the instance's clip plays the
// pair's lower clip and its overlay the upper one on the space's mask, both started at the same
// phase of their cycles and advancing at their durations over the blended period, so they stay
// in step; each parameter change re-anchors both at the phase reached.
#include <algorithm>
#include <cmath>
#include <limits>

#include "crowd/instance_root_motion.h"
#include "crowd/instance_store.h"

namespace si::detail {

void InstanceStore::anchorBlend(uint32_t i, const BlendSpace& space, float parameter, double phase,
                                double clock) {
  OverlayState& o = overlays[i];
  parameter = std::clamp(parameter, space.positions.front(), space.positions.back());
  const BlendPair pair = blendPair(space.positions, parameter);
  const uint32_t lower = space.clips[pair.lower], upper = space.clips[pair.upper];
  const double lower_seconds = (*clip_timings)[lower].duration;
  const double upper_seconds = (*clip_timings)[upper].duration;
  const double period = blendPeriod(lower_seconds, upper_seconds, pair.weight);
  const double rate = period > 0.0 ? double(o.blend_speed) / period : 0.0;
  if (phase >= 1.0 || phase < 0.0) phase -= std::floor(phase);  // Cycles repeat.
  if (!(phase >= 0.0 && phase < 1.0)) phase = 0.0;
  // Each clip at its duration over the period, held within a float (a huge speed over clips of
  // very different lengths would pass it).
  const auto speedOf = [&](double seconds) {
    return float(std::min(seconds * rate, double(std::numeric_limits<float>::max())));
  };
  // The instance's clip: a crossfade under way keeps fading from what it came from.
  playback[i] = Playback{lower, palette->clips[lower].loop_mode, speedOf(lower_seconds), clock,
                         phase * lower_seconds};
  o.playback = Playback{upper, palette->clips[upper].loop_mode, speedOf(upper_seconds), clock,
                        phase * upper_seconds};
  o.mask = space.mask;
  if (o.fade_duration > 0.0 && clock < o.fade_start + o.fade_duration) {
    // Still fading: on from the weight reached towards the new one, over the span left.
    const double end = o.fade_start + o.fade_duration;
    o.weight_from = overlayWeight(o, clock);
    o.weight_to = pair.weight;
    o.fade_start = clock;
    o.fade_duration = end - clock;
  } else {
    o.weight_from = o.weight_to = pair.weight;
    o.fade_duration = 0.0;
  }
  o.parameter = parameter;
  o.phase = phase;
  o.phase_clock = clock;
  o.cycles_per_second = rate;
  changed(i);
}

Status InstanceStore::playBlend(InstanceHandle h, const BlendSpace& space, uint32_t space_id,
                                float parameter, double blend_seconds, double phase, float speed,
                                double clock) {
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
                                        float parameter, double clock) {
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
