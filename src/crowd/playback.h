// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Playback time of an instance, derived from the crowd clock (never accumulated per instance,
// so it does not drift), and the frame sample of a clip at that time.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/frame_times_sample.h"
#include "si/core/baked_palette.h"

namespace si::detail {

/// One clip playing on an instance.
struct Playback {
  uint32_t clip;
  LoopMode loop;        // kLoop or kOnce (kDefault resolved when it starts).
  float speed;
  double start_clock;   // Crowd clock when this playback started.
  double start_time;    // Clip-local time at start_clock.
};

/// What the per-frame work needs of a clip, compact and with reciprocals.
struct ClipTiming {
  double duration, inv_duration, interval, inv_interval;
  uint32_t first_texel, last_interval;
  bool uniform;  // No STEP frames: the frame follows from the time alone.
  bool plain;    // Uniform and every interval linear (no interval modes).
  glm::vec3 sphere_center;
  float sphere_radius;
  // Clips with frame times (STEP keys, frames at keys): per cell of 1 / inv_cell seconds
  // (four cells per frame), the last frame in an earlier cell, so a frame is found in a step or
  // two however unevenly the frames are spaced (the grid of frame_interval_seconds is as wide
  // as the widest gap).
  std::vector<uint32_t> cell_frame;
  double inv_cell;
  // The clip's interval modes (empty for linear clips): read here, next to the timing the
  // record writer already holds, instead of from the BakedClip.
  std::vector<uint8_t> modes;
  // Root motion: the cosine and sine of each frame's baked yaw (empty without root motion).
  std::vector<glm::dvec2> yaw_cos_sin;
};


inline ClipTiming makeClipTiming(const BakedClip& c) {
  ClipTiming t;
  t.duration = c.duration_seconds;
  t.inv_duration = c.duration_seconds > 0.0f ? 1.0 / c.duration_seconds : 0.0;
  t.interval = c.frame_interval_seconds;
  t.inv_interval = c.frame_interval_seconds > 0.0 ? 1.0 / c.frame_interval_seconds : 0.0;
  t.first_texel = c.first_texel;
  t.last_interval = c.frame_count >= 2 ? c.frame_count - 2 : 0;
  t.uniform = c.frame_times_seconds.empty() && c.frame_count >= 2 && t.interval > 0.0;
  t.sphere_center = c.bounding_sphere.center;
  t.sphere_radius = c.bounding_sphere.radius;
  t.inv_cell = 0.0;
  const std::vector<double>& times = c.frame_times_seconds;
  if (!t.uniform && times.size() == c.frame_count && c.frame_count >= 2 &&
      c.duration_seconds > 0.0f) {
    const size_t cells = size_t(c.frame_count) * 4;
    t.inv_cell = double(cells) / double(c.duration_seconds);
    t.cell_frame.assign(cells + 1, 0);
    // cell_frame[k] = the last frame whose cell (floor(time * inv_cell)) is below k: the same
    // product the lookup takes, so a frame found there is never after the time looked up.
    size_t f = 0;
    for (size_t k = 1; k <= cells; ++k) {
      while (f + 1 < times.size() && times[f + 1] * t.inv_cell < double(k)) ++f;
      t.cell_frame[k] = uint32_t(f);
    }
  }
  t.modes = c.interval_modes;
  t.plain = t.uniform && t.modes.empty();
  for (const glm::vec3& m : c.root_motion)
    t.yaw_cos_sin.push_back({std::cos(double(m.z)), std::sin(double(m.z))});
  return t;
}

/// Clip-local time of `p` at crowd clock `clock`: wrapped for loops, clamped otherwise; always
/// within [0, duration] (0 when the unwrapped time overflows: a hostile speed or start time).
/// The time animation-LOD stepping draws an instance at (CrowdDesc::animation_lod_start and
/// animation_lod_rate_hz): `t` held on the grid of `step_seconds`. The records and
/// CrowdManager::jointMatrix both step through it.
inline double steppedTime(double t, double step_seconds) {
  return std::floor(t / step_seconds) * step_seconds;
}

inline double localTime(const Playback& p, const ClipTiming& c, double clock) {
  const double duration = c.duration;
  const double t = p.start_time + (clock - p.start_clock) * double(p.speed);
  if (!(duration > 0.0) || !std::isfinite(t)) return 0.0;
  if (p.loop == LoopMode::kLoop) {
    // t - floor(t / d) * d: the same as fmod for these magnitudes, and several times cheaper.
    double w = t - std::floor(t * c.inv_duration) * duration;
    if (w < 0.0) w += duration;
    if (w >= 0.0 && w < duration) return w;
    // Past 2^53 intervals the product loses the fraction: the exact remainder instead.
    w = std::fmod(t, duration);
    if (w < 0.0) w += duration;
    return w >= 0.0 && w < duration ? w : 0.0;
  }
  return std::clamp(t, 0.0, duration);
}

/// si::sampleFrames(clip, t) for t within [0, duration], with a reciprocal instead of a
/// division on uniform grids.
inline FrameSample fastSample(const ClipTiming& c, const BakedClip& clip, double t) {
  if (!c.uniform) {
    if (c.cell_frame.empty()) return sampleFrames(clip, t);
    // sampleFrames(clip, t) from the cell table: the last frame at or before t.
    const double tc = t > 0.0 ? std::min(t, double(clip.duration_seconds)) : 0.0;
    const std::vector<double>& times = clip.frame_times_seconds;
    const double cell = std::floor(tc * c.inv_cell);
    size_t after = c.cell_frame[std::min(size_t(cell), c.cell_frame.size() - 1)] + 1;
    while (after < times.size() && times[after] <= tc) ++after;
    return frameTimesSample(clip, tc, after);
  }
  const double position = t * c.inv_interval;
  // Compared before the conversion: a position past the last interval never converts.
  const uint32_t i = position >= double(c.last_interval) ? c.last_interval
                     : position > 0.0                    ? static_cast<uint32_t>(position)
                                                         : 0u;
  FrameSample s;
  s.frame = i;
  s.next_frame = i + 1;
  s.fraction = static_cast<float>(std::min(std::max(position - double(i), 0.0), 1.0));
  s.mode = intervalModeAt(c.modes, i);
  return s;
}

/// The frame sample a crowd takes of clip-local `t` (clamped to the clip) of `clip`: its
/// timing made as a crowd makes it, then fastSample. For tests and tools.
inline FrameSample clipFrameSample(const BakedClip& clip, double t) {
  const ClipTiming c = makeClipTiming(clip);
  return fastSample(c, clip, std::min(std::max(t, 0.0), c.duration));
}

}  // namespace si::detail
