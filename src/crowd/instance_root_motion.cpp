// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd/instance_root_motion.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "si/core/root_motion.h"

namespace si::detail {

namespace {

// The per-instance helpers below are small and called once per instance per update.
#if defined(__GNUC__) || defined(__clang__)
#define SI_INLINE inline __attribute__((always_inline))
#else
#define SI_INLINE inline
#endif

// sin and cos of x: a Taylor polynomial for |x| <= 1/4 (error below 1e-14: the per-frame and
// per-step angles root motion turns by are small), the library's otherwise.
SI_INLINE void sinCos(double x, double* s, double* c) {
  if (!(std::fabs(x) <= 0.25)) {
    *s = std::sin(x);
    *c = std::cos(x);
    return;
  }
  const double x2 = x * x;
  *s = x * (1.0 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 +
                                                                            x2 * (-1.0 / 39916800))))));
  *c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 +
                                                                 x2 * (-1.0 / 3628800)))));
}

// The baked motion M at clip-local time t (within [0, duration]) of a uniform clip, as
// si::sampleRootMotion gives it (the crowd's reciprocal for the frame), and the cosine and sine
// of its yaw: frame a's from the table, turned by the lerp's share of the interval's turn.
struct MotionAt {
  glm::dvec2 translation;
  double yaw, cos_yaw, sin_yaw;
};
SI_INLINE MotionAt uniformMotionAt(const BakedClip& clip, const ClipTiming& c, double t) {
  const FrameSample s = fastSample(c, clip, t);
  const glm::vec3& a = clip.root_motion[s.frame];
  const glm::vec3& b = clip.root_motion[s.next_frame];
  const double f = double(s.fraction);
  const double turn = (double(b.z) - a.z) * f;
  double sn = 0.0, cs = 1.0;
  sinCos(turn, &sn, &cs);
  const glm::dvec2 base = c.yaw_cos_sin[s.frame];
  return {{a.x + (double(b.x) - a.x) * f, a.y + (double(b.y) - a.y) * f}, a.z + turn,
          base.x * cs - base.y * sn, base.y * cs + base.x * sn};
}

// The baked motion of playback `p` between crowd clocks c0 <= c1 (from its start at the
// latest): M(u0)^-1 * M(u1). Within one cycle of a uniform clip (almost every step) that is
// (R(-yaw0) (t1 - t0), yaw1 - yaw0) from two lerps, the cosine table and small-angle
// polynomials; otherwise si::rootMotionBetween.
SI_INLINE GroundMotion playbackMotion(const BakedPalette& palette, const std::vector<ClipTiming>& clips,
                            const Playback& p, double c0, double c1) {
  const BakedClip& clip = palette.clips[p.clip];
  if (clip.root_motion.empty()) return {};
  c0 = std::max(c0, p.start_clock);
  if (!(c1 > c0)) return {};
  const double speed = double(p.speed);
  const double u0 = p.start_time + (c0 - p.start_clock) * speed;
  const double u1 = p.start_time + (c1 - p.start_clock) * speed;
  const ClipTiming& c = clips[p.clip];
  if (c.uniform && std::isfinite(u0) && std::isfinite(u1)) {
    // A loop's cycle k is shifted back to the first; a step within one cycle needs no more.
    const double k = p.loop == LoopMode::kLoop ? std::floor(u0 * c.inv_duration) : 0.0;
    const double w0 = u0 - k * c.duration, w1 = u1 - k * c.duration;
    if (w0 >= 0.0 && w0 <= w1 && w1 <= c.duration * (1.0 - 1e-12)) {
      const MotionAt a = uniformMotionAt(clip, c, w0), b = uniformMotionAt(clip, c, w1);
      const glm::dvec2 d = b.translation - a.translation;
      return {{a.cos_yaw * d.x - a.sin_yaw * d.y, a.sin_yaw * d.x + a.cos_yaw * d.y},
              b.yaw - a.yaw};
    }
  }
  return rootMotionBetween(clip, p.loop, u0, u1);
}

}  // namespace

void applyRootMotion(const BakedPalette& palette, const std::vector<ClipTiming>& clips,
                     double clock, InstanceStore& st, uint32_t i) {
  const double since = st.motion_clock[i];
  st.motion_clock[i] = clock;
  if (!(clock > since)) return;
  GroundMotion m = playbackMotion(palette, clips, st.playback[i], since, clock);
  const double fade_end = st.fade_start[i] + st.fade_duration[i];
  if (st.fade_duration[i] > 0.0 && since < fade_end) {  // The fade ran during the step.
    const GroundMotion old =
        playbackMotion(palette, clips, st.fade_from[i], since, std::min(clock, fade_end));
    const double middle = 0.5 * (since + clock);
    const double w = std::clamp((middle - st.fade_start[i]) / st.fade_duration[i], 0.0, 1.0);
    m.translation = old.translation + (m.translation - old.translation) * w;
    m.yaw = old.yaw + (m.yaw - old.yaw) * w;
  }
  const OverlayState& o = st.overlays[i];
  if (o.blend) {  // A blend travels as it blends: each layer's motion by its weight in turn.
    const double middle = 0.5 * (since + clock);
    const auto mixIn = [&](const Playback& p, double w) {
      if (!(w > 0.0)) return;
      const GroundMotion up = playbackMotion(palette, clips, p, since, clock);
      m.translation += (up.translation - m.translation) * w;
      m.yaw += (up.yaw - m.yaw) * w;
    };
    mixIn(o.playback, double(overlayWeight(o, middle)));
    for (uint32_t k = 0; k < kExtraLayers; ++k)
      mixIn(o.extra[k].playback, double(extraWeight(o, k, middle)));
  }
  if (m.translation == glm::dvec2(0.0) && m.yaw == 0.0) return;
  const glm::quat r = st.rotations.get(i);
  const glm::vec3 step =
      r * (st.scales[i] * glm::vec3(float(m.translation.x), 0.0f, float(m.translation.y)));
  const glm::dvec3 position = st.positions.get(i) + glm::dvec3(step);
  double sn = 0.0, cs = 1.0;
  sinCos(0.5 * m.yaw, &sn, &cs);
  const glm::quat turned = glm::normalize(r * glm::quat(float(cs), 0.0f, float(sn), 0.0f));
  if (!std::isfinite(position.x + position.y + position.z) ||
      !std::isfinite(turned.w + turned.x + turned.y + turned.z))
    return;
  st.positions.set(i, position);
  st.rotations.set(i, turned);
}

void applyRootMotion(const BakedPalette& palette, const std::vector<ClipTiming>& clips,
                     double clock, InstanceStore& st, uint32_t begin, uint32_t end) {
  for (uint32_t i = begin; i < end; ++i) {
    if (!st.root_motion[i]) continue;
    const glm::dvec3 position = st.positions.get(i);
    const glm::quat rotation = st.rotations.get(i);
    applyRootMotion(palette, clips, clock, st, i);
    // Bitwise: a turn that only flips a zero's sign changes what the GPU state exports.
    const glm::dvec3 moved = st.positions.get(i);
    const glm::quat turned = st.rotations.get(i);
    if (std::memcmp(&moved, &position, sizeof(moved)) != 0 ||
        std::memcmp(&turned, &rotation, sizeof(turned)) != 0)
      st.stamp(i);
  }
}

}  // namespace si::detail
