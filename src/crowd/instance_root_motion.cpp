// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd/instance_root_motion.h"

#include <algorithm>
#include <cmath>

#include "si/core/root_motion.h"

namespace si::detail {

namespace {
// The baked motion of playback `p` between crowd clocks c0 <= c1 (from its start at the latest).
GroundMotion playbackMotion(const BakedPalette& palette, const Playback& p, double c0, double c1) {
  const BakedClip& clip = palette.clips[p.clip];
  if (clip.root_motion.empty()) return {};
  c0 = std::max(c0, p.start_clock);
  if (!(c1 > c0)) return {};
  const double speed = double(p.speed);
  return rootMotionBetween(clip, p.loop, p.start_time + (c0 - p.start_clock) * speed,
                           p.start_time + (c1 - p.start_clock) * speed);
}
}  // namespace

void applyRootMotion(const BakedPalette& palette, double clock, InstanceStore& st, uint32_t i) {
  const double since = st.motion_clock[i];
  st.motion_clock[i] = clock;
  if (!(clock > since)) return;
  GroundMotion m = playbackMotion(palette, st.playback[i], since, clock);
  if (st.fade_duration[i] > 0.0) {
    const double fade_end = st.fade_start[i] + st.fade_duration[i];
    const GroundMotion old =
        playbackMotion(palette, st.fade_from[i], since, std::min(clock, fade_end));
    const double middle = 0.5 * (since + clock);
    const double w = std::clamp((middle - st.fade_start[i]) / st.fade_duration[i], 0.0, 1.0);
    m.translation = old.translation + (m.translation - old.translation) * w;
    m.yaw = old.yaw + (m.yaw - old.yaw) * w;
  }
  if (m.translation == glm::dvec2(0.0) && m.yaw == 0.0) return;
  const glm::dquat rotation(st.rotations[i]);
  const glm::dvec3 position =
      st.positions[i] +
      rotation * (double(st.scales[i]) * glm::dvec3(m.translation.x, 0.0, m.translation.y));
  const glm::quat turned = glm::normalize(
      st.rotations[i] * glm::angleAxis(float(m.yaw), glm::vec3(0.0f, 1.0f, 0.0f)));
  if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z) ||
      !isFinite(turned))
    return;
  st.positions[i] = position;
  st.rotations[i] = turned;
}

void applyRootMotion(const BakedPalette& palette, double clock, InstanceStore& st,
                     uint32_t begin, uint32_t end) {
  for (uint32_t i = begin; i < end; ++i)
    if (st.root_motion[i]) applyRootMotion(palette, clock, st, i);
}

}  // namespace si::detail
