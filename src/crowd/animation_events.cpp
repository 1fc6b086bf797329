// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd/animation_events.h"

#include <algorithm>
#include <cmath>

namespace si::detail {

uint32_t markerPasses(const Playback& p, double duration, double t, double c0, double c1,
                      bool from_start) {
  const double speed = double(p.speed);
  const double u0 = p.start_time + (c0 - p.start_clock) * speed;
  const double u1 = p.start_time + (c1 - p.start_clock) * speed;
  if (!std::isfinite(u0) || !std::isfinite(u1) || !(u1 >= u0)) return 0;
  if (p.loop == LoopMode::kLoop && duration > 0.0) {
    // Passes up to x: floor((x - t) / d) + const; strictly before x: ceil((x - t) / d) - 1.
    const double upto = std::floor((u1 - t) / duration);
    const double before =
        from_start ? std::ceil((u0 - t) / duration) - 1.0 : std::floor((u0 - t) / duration);
    const double n = upto - before;
    if (!(n > 0.0)) return 0;
    return n >= 4294967295.0 ? 4294967295u : static_cast<uint32_t>(n);
  }
  // Played once: clamped to [0, duration], each marker passes at most once.
  const double v0 = std::clamp(u0, 0.0, duration), v1 = std::clamp(u1, 0.0, duration);
  return (from_start ? v0 <= t : v0 < t) && t <= v1 ? 1u : 0u;
}

void collectEvents(const MarkerTable& table, const std::vector<ClipTiming>& clips, double clock,
                   InstanceStore& st, uint32_t begin, uint32_t end,
                   std::vector<AnimationEvent>* out) {
  const auto report = [&](uint32_t i, const Playback& p, double c0, double c1, bool from_start) {
    for (uint32_t m : table.clip_markers[p.clip]) {
      const uint32_t n = markerPasses(p, clips[p.clip].duration, table.markers[m].time_seconds, c0,
                                      c1, from_start);
      if (n > 0) out->push_back(AnimationEvent{st.dense_handles[i], m, n});
    }
  };
  for (uint32_t i = begin; i < end; ++i) {
    const double since = st.events_clock[i];
    // The clip fading out: from the last report until the fade ends (or now).
    if (st.fade_duration[i] > 0.0 && !table.clip_markers[st.fade_from[i].clip].empty()) {
      const double fade_end = st.fade_start[i] + st.fade_duration[i];
      const double until = std::min(clock, fade_end);
      if (until > since) report(i, st.fade_from[i], since, until, false);
    }
    const Playback& p = st.playback[i];
    if (!table.clip_markers[p.clip].empty()) {
      const bool fresh = st.events_new[i] != 0;
      report(i, p, fresh ? p.start_clock : since, clock, fresh);
    }
    st.events_clock[i] = clock;
    st.events_new[i] = 0;
  }
}

}  // namespace si::detail
