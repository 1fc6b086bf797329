// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Animation events: markers in clip time (ClipMarker) and the events an update reports when an
/// instance's playback passes one (AnimationEvent; CrowdManager::addClipMarker, events()).

#include <cstdint>
#include <string>

#include "si/crowd/handle_pool.h"

namespace si {

/// A named point in a clip's time (an animation event: a footstep, a hit), added with
/// CrowdManager::addClipMarker.
struct ClipMarker {
  uint32_t clip = 0;          ///< Index into the palette's clips.
  double time_seconds = 0.0;  ///< Clip-local, within [0, duration].
  std::string name;
};

/// An instance's playback passed a marker during the last update(): `count` times (more than
/// once when a looping clip wrapped several times in one step).
struct AnimationEvent {
  InstanceHandle instance;
  uint32_t marker = 0;  ///< Index into CrowdManager::clipMarkers().
  uint32_t count = 1;
};

}  // namespace si
