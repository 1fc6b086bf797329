// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Root motion: ground-plane motions, the root joint of a clip, and the baked motion's sampling.
// The evaluation of M(t) from a clip's tracks is the reference evaluator's
// (reference_evaluator.cpp); the ground frame of a model matrix is here (core/root_motion_frame.h).
#include "si/core/root_motion.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "core/root_motion_frame.h"
#include "core/str_cat.h"
#include "si/core/baked_palette.h"
#include "si/core/clip.h"
#include "si/core/skeleton.h"

namespace si {
using detail::strCat;

namespace {
constexpr double kPi = 3.14159265358979323846;

// R_y(yaw) applied to (x, 0, z), as (x, z).
glm::dvec2 rotateY(double yaw, const glm::dvec2& v) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * v.x + s * v.y, -s * v.x + c * v.y};
}

}  // namespace

double wrapAngle(double radians) {
  const double a = std::remainder(radians, 2.0 * kPi);  // [-pi, pi]
  return a <= -kPi ? a + 2.0 * kPi : a;
}

glm::dmat4 groundMotionMatrix(const GroundMotion& m) {
  const double c = std::cos(m.yaw), s = std::sin(m.yaw);
  glm::dmat4 out(1.0);
  out[0] = glm::dvec4(c, 0.0, -s, 0.0);
  out[2] = glm::dvec4(s, 0.0, c, 0.0);
  out[3] = glm::dvec4(m.translation.x, 0.0, m.translation.y, 1.0);
  return out;
}

GroundMotion composeGroundMotion(const GroundMotion& a, const GroundMotion& b) {
  return {a.translation + rotateY(a.yaw, b.translation), a.yaw + b.yaw};
}

GroundMotion inverseGroundMotion(const GroundMotion& m) {
  return {-rotateY(-m.yaw, m.translation), -m.yaw};
}

GroundMotion repeatGroundMotion(const GroundMotion& m, uint64_t count) {
  GroundMotion result, power = m;
  for (; count != 0; count >>= 1) {
    if (count & 1u) result = composeGroundMotion(result, power);
    power = composeGroundMotion(power, power);
  }
  return result;
}

Status rootMotionJoint(const Skeleton& skeleton, const Clip& clip, uint32_t* joint) {
  if (!clip.root_motion.joint.empty()) {
    const int32_t j = skeleton.findJoint(clip.root_motion.joint);
    if (j < 0)
      return {StatusCode::kNotFound, strCat("clip '", clip.name, "': root motion joint '",
                                            clip.root_motion.joint, "' is not in the skeleton")};
    *joint = uint32_t(j);
    return Status::ok();
  }
  const size_t n = std::min(skeleton.jointCount(), clip.joint_tracks.size());
  for (size_t j = 0; j < n; ++j)
    if (!clip.joint_tracks[j].translation.empty()) return *joint = uint32_t(j), Status::ok();
  for (size_t j = 0; j < n; ++j)
    if (!clip.joint_tracks[j].rotation.empty()) return *joint = uint32_t(j), Status::ok();
  *joint = 0;
  return Status::ok();
}

namespace detail {

double groundYaw(const glm::dmat4& model) {
  glm::dvec3 c0(model[0]), c1(model[1]), c2(model[2]);
  const double l0 = glm::length(c0), l1 = glm::length(c1), l2 = glm::length(c2);
  if (!(l0 > 1e-300 && l1 > 1e-300 && l2 > 1e-300)) return 0.0;  // Zero scale: no direction.
  c0 /= l0, c1 /= l1, c2 /= l2;
  if (glm::dot(glm::cross(c0, c1), c2) < 0.0) c2 = -c2;  // Mirrored: the rotation part.
  const glm::dquat q = glm::quat_cast(glm::dmat3(c0, c1, c2));
  // The twist of q about +Y: its (w, y) components (the same for swing-twist in either order).
  if (std::fabs(q.w) < 1e-12 && std::fabs(q.y) < 1e-12) return 0.0;  // Upside down: none.
  return wrapAngle(2.0 * std::atan2(q.y, q.w));
}

GroundMotion groundMotionBetween(const glm::dmat4& model_at_start, const glm::dmat4& model_at_t) {
  // Ground frames G = T(x, 0, z) * R_y(yaw); M = G(t) * G(0)^-1.
  const GroundMotion g0{{model_at_start[3].x, model_at_start[3].z}, groundYaw(model_at_start)};
  const GroundMotion gt{{model_at_t[3].x, model_at_t[3].z}, groundYaw(model_at_t)};
  GroundMotion m = composeGroundMotion(gt, inverseGroundMotion(g0));
  m.yaw = wrapAngle(m.yaw);
  return m;
}

}  // namespace detail

GroundMotion sampleRootMotion(const BakedClip& clip, const FrameSample& sample) {
  const size_t n = clip.root_motion.size();
  if (n == 0) return {};
  const glm::dvec3 a(clip.root_motion[std::min<size_t>(sample.frame, n - 1)]);
  const glm::dvec3 b(clip.root_motion[std::min<size_t>(sample.next_frame, n - 1)]);
  const glm::dvec3 v = a + (b - a) * double(sample.fraction);
  return {{v.x, v.y}, v.z};
}

GroundMotion rootMotionAt(const BakedClip& clip, double local_time_seconds) {
  if (clip.root_motion.empty()) return {};
  return sampleRootMotion(clip, sampleFrames(clip, local_time_seconds));
}

GroundMotion rootMotionBetween(const BakedClip& clip, LoopMode loop, double from_seconds,
                               double to_seconds) {
  if (clip.root_motion.empty() || !std::isfinite(from_seconds) || !std::isfinite(to_seconds))
    return {};
  const double d = clip.duration_seconds;
  if (resolveLoopMode(loop) != LoopMode::kLoop || !(d > 0.0)) {
    const double a = std::clamp(from_seconds, 0.0, std::max(d, 0.0));
    const double b = std::clamp(to_seconds, 0.0, std::max(d, 0.0));
    return composeGroundMotion(inverseGroundMotion(rootMotionAt(clip, a)), rootMotionAt(clip, b));
  }
  if (to_seconds < from_seconds)
    return inverseGroundMotion(rootMotionBetween(clip, loop, to_seconds, from_seconds));
  const double k0 = std::floor(from_seconds / d), k1 = std::floor(to_seconds / d);
  const double w0 = std::clamp(from_seconds - k0 * d, 0.0, d);
  const double w1 = std::clamp(to_seconds - k1 * d, 0.0, d);
  const double cycles = std::min(k1 - k0, double(uint64_t(1) << 20));
  const GroundMotion cycle = sampleRootMotion(
      clip, FrameSample{clip.frame_count - 1, clip.frame_count - 1, 0.0f, IntervalMode::kLinear});
  const GroundMotion between =
      cycles > 0.0 ? repeatGroundMotion(cycle, uint64_t(cycles)) : GroundMotion{};
  return composeGroundMotion(inverseGroundMotion(rootMotionAt(clip, w0)),
                             composeGroundMotion(between, rootMotionAt(clip, w1)));
}

RootMotionSummary summarizeRootMotion(const BakedClip& clip) {
  RootMotionSummary s;
  if (clip.root_motion.empty()) return s;
  const glm::dvec3 last(clip.root_motion.back());
  s.whole_clip = {{last.x, last.y}, last.z};
  if (clip.duration_seconds > 0.0f) {
    s.average_velocity = s.whole_clip.translation / double(clip.duration_seconds);
    s.average_yaw_rate = s.whole_clip.yaw / double(clip.duration_seconds);
    s.average_speed = glm::length(s.average_velocity);
  }
  return s;
}

}  // namespace si
