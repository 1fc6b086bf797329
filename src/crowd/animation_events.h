// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Animation events: which clip markers each instance's playback passed between the crowd clock
// it last reported at and now. Playback time is a line in unwrapped clip time
// (start_time + (clock - start_clock) * speed), so the passes of a marker at T of a looping
// clip of duration d in a span (u0, u1] are the k with u0 < T + k d <= u1: counted, not
// stepped, whatever the time step. A playback that started since the last report counts from
// its start inclusive; the clip that fades out during a crossfade counts until the fade ends.

#include <cstdint>
#include <utility>
#include <vector>

#include "crowd/instance_store.h"
#include "crowd/playback.h"
#include "si/crowd/animation_event.h"

namespace si::detail {

/// The crowd's markers by clip.
struct MarkerTable {
  std::vector<ClipMarker> markers;                  // As added (AnimationEvent::marker indexes).
  std::vector<std::vector<uint32_t>> clip_markers;  // Per palette clip: its markers' indices.
  bool empty() const { return markers.empty(); }
  /// Appends `m` (its clip below clip_markers.size()) and returns its index.
  uint32_t add(ClipMarker m) {
    const uint32_t index = uint32_t(markers.size());
    clip_markers[m.clip].push_back(index);
    markers.push_back(std::move(m));
    return index;
  }
};

/// Passes of marker time `t` by playback `p` of a clip of `duration` seconds between crowd
/// clocks `c0` and `c1` (c0 <= c1): (c0, c1], or [c0, c1] when `from_start` (a playback
/// reported from its start: c0 is its start clock).
uint32_t markerPasses(const Playback& p, double duration, double t, double c0, double c1,
                      bool from_start);

/// Appends the events of instances [begin, end) up to `clock` to `out` (dense order) and marks
/// them reported at `clock`.
void collectEvents(const MarkerTable& table, const std::vector<ClipTiming>& clips, double clock,
                   InstanceStore& st, uint32_t begin, uint32_t end,
                   std::vector<AnimationEvent>* out);

}  // namespace si::detail
