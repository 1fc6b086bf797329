// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The embedded character's clips: each joint's local rotation (and translations) as periodic
// functions of time, sampled into keyframe tracks.
#include <cmath>
#include <functional>

#include "core/default_skeleton.h"

namespace si::detail::embedded {
namespace {

// ---------------------------------------------------------------------------------------------
// Clips: each joint's local rotation (and the pelvis translation) as a function of time.

glm::dquat axisAngle(double angle, const glm::dvec3& axis) {
  return glm::dquat(std::cos(angle / 2), axis * std::sin(angle / 2));
}
const glm::dvec3 kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1);

struct ClipDef {
  const char* name;
  double duration;
  LoopMode loop;
  int key_count;  // Keys including both ends.
  Interpolation interpolation;
  // Rotation of joint j at time t, or nullopt-like identity flag through `animated`.
  std::function<bool(int joint, double t, glm::dquat* rotation)> rotation;
  std::function<bool(int joint, double t, glm::dvec3* translation)> translation;
  int step_joint = -1;  // A joint whose rotation track uses STEP keys.
};

// A clip's header: its name, length, loop mode and key count, keys interpolated `interpolation`.
ClipDef clipHeader(const char* name, double duration, LoopMode loop, int key_count,
                   Interpolation interpolation = Interpolation::kLinear) {
  return ClipDef{name, duration, loop, key_count, interpolation, {}, {}};
}

// Central differences of samples a (at t - h) and b (at t + h), a CUBICSPLINE key's tangent.
glm::dquat centralDifference(const glm::dquat& a, const glm::dquat& b, double h) {
  return (b - a) * (1.0 / (2 * h));
}
glm::dvec3 centralDifference(const glm::dvec3& a, const glm::dvec3& b, double h) {
  return (b - a) / (2 * h);
}
glm::quat toFloat(const glm::dquat& q) {
  return glm::quat(float(q.w), float(q.x), float(q.y), float(q.z));
}
glm::vec3 toFloat(const glm::dvec3& v) {
  return glm::vec3(v);
}

// Fills `track` with `def`'s evenly spaced keys of joint `j` from `sample(j, t, &value)` (a
// CUBICSPLINE track: in-tangent, value, out-tangent a key).
template <class Track, class Value, class Sample>
void sampleKeys(const ClipDef& def, int j, const Sample& sample, Track* track) {
  const double h = 1e-5;
  const bool cubic = track->interpolation == Interpolation::kCubicSpline;
  for (int k = 0; k < def.key_count; ++k) {
    const double t = def.duration * k / (def.key_count - 1);
    track->times_seconds.push_back(static_cast<float>(t));
    Value v{}, before{}, after{};
    sample(j, t, &v);
    if (cubic) {
      sample(j, t - h, &before);
      sample(j, t + h, &after);
      const auto tangent = toFloat(centralDifference(before, after, h));
      track->values.insert(track->values.end(), {tangent, toFloat(v), tangent});
    } else {
      track->values.push_back(toFloat(v));
    }
  }
}

Clip buildClip(const ClipDef& def) {
  Clip clip;
  clip.name = def.name;
  clip.duration_seconds = static_cast<float>(def.duration);
  clip.loop_mode = def.loop;
  clip.joint_tracks.resize(kJointCount);
  for (int j = 0; j < kJointCount; ++j) {
    glm::dquat q;
    glm::dvec3 tr;
    JointTracks& jt = clip.joint_tracks[size_t(j)];
    if (def.rotation && def.rotation(j, 0.0, &q)) {
      jt.rotation.interpolation = j == def.step_joint ? Interpolation::kStep : def.interpolation;
      sampleKeys<QuatTrack, glm::dquat>(def, j, def.rotation, &jt.rotation);
    }
    if (def.translation && def.translation(j, 0.0, &tr)) {
      jt.translation.interpolation = def.interpolation;
      sampleKeys<Vec3Track, glm::dvec3>(def, j, def.translation, &jt.translation);
    }
  }
  return clip;
}


// Walk and run share one gait with different amplitudes.
struct Gait {
  double period, thigh, knee_base, knee, arm, elbow, lean, bob, twist;
};

ClipDef gaitClip(const char* name, const Gait& g, int keys, Interpolation interpolation) {
  ClipDef def = clipHeader(name, g.period, LoopMode::kLoop, keys, interpolation);
  def.rotation = [g](int j, double t, glm::dquat* q) {
    const double p = 2 * kPi * t / g.period, s = std::sin(p), c = std::cos(p);
    switch (j) {
      case kPelvis: *q = axisAngle(g.twist * s, kY); return true;
      case kSpine: *q = axisAngle(g.lean, kX) * axisAngle(-0.6 * g.twist * s, kY); return true;
      case kChest: *q = axisAngle(-0.6 * g.twist * s, kY); return true;
      case kHead: *q = axisAngle(-0.5 * g.lean + 0.03 * std::sin(2 * p), kX); return true;
      case kLThigh: *q = axisAngle(-g.thigh * s, kX); return true;
      case kRThigh: *q = axisAngle(g.thigh * s, kX); return true;
      case kLShin: *q = axisAngle(g.knee_base + g.knee * (1 - c) / 2, kX); return true;
      case kRShin: *q = axisAngle(g.knee_base + g.knee * (1 + c) / 2, kX); return true;
      case kLFoot: *q = axisAngle(0.25 * g.thigh * s, kX); return true;
      case kRFoot: *q = axisAngle(-0.25 * g.thigh * s, kX); return true;
      case kLUpperArm: *q = axisAngle(g.arm * s, kX) * axisAngle(0.08, kZ); return true;
      case kRUpperArm: *q = axisAngle(-g.arm * s, kX) * axisAngle(-0.08, kZ); return true;
      case kLForearm: *q = axisAngle(-g.elbow - 0.3 * g.elbow * s, kX); return true;
      case kRForearm: *q = axisAngle(-g.elbow + 0.3 * g.elbow * s, kX); return true;
      default: return false;
    }
  };
  def.translation = [g](int j, double t, glm::dvec3* tr) {
    if (j != kPelvis) return false;
    const double p = 2 * kPi * t / g.period;
    *tr = restOffset(kPelvis) + glm::dvec3(0, g.bob * std::cos(2 * p) - g.bob, 0);
    return true;
  };
  return def;
}

// A gait that travels: the root joint (a game rig's root bone, at the feet) moves forward (+Z,
// the way the character faces) at `speed` units per second while turning left (about +Y) at
// `yaw_rate` radians per second, on the arc that keeps it moving the way it faces.
ClipDef travelingClip(const char* name, ClipDef gait, double speed, double yaw_rate) {
  gait.name = name;
  const auto rotation = gait.rotation;
  const auto translation = gait.translation;
  gait.rotation = [rotation, yaw_rate](int j, double t, glm::dquat* q) {
    if (j != kRoot) return rotation(j, t, q);
    *q = axisAngle(yaw_rate * t, kY);
    return yaw_rate != 0.0;
  };
  gait.translation = [translation, speed, yaw_rate](int j, double t, glm::dvec3* tr) {
    if (j != kRoot) return translation(j, t, tr);
    const double a = yaw_rate * t;
    *tr = restOffset(kRoot) + (yaw_rate == 0.0 ? glm::dvec3(0, 0, speed * t)
                                               : speed / yaw_rate *
                                                     glm::dvec3(1 - std::cos(a), 0, std::sin(a)));
    return true;
  };
  return gait;
}

ClipDef idleClip() {
  ClipDef def = clipHeader("idle", 3.0, LoopMode::kLoop, 31);
  def.rotation = [](int j, double t, glm::dquat* q) {
    const double p = 2 * kPi * t / 3.0, s = std::sin(p);
    switch (j) {
      case kSpine: *q = axisAngle(0.02 * s, kX); return true;
      case kChest: *q = axisAngle(0.03 * s, kX); return true;
      case kHead: *q = axisAngle(0.15 * std::sin(p + 1.0), kY); return true;
      case kLUpperArm: *q = axisAngle(0.05 + 0.03 * s, kZ); return true;
      case kRUpperArm: *q = axisAngle(-0.05 - 0.03 * s, kZ); return true;
      case kLForearm: *q = axisAngle(-0.15, kX); return true;
      case kRForearm: *q = axisAngle(-0.15, kX); return true;
      default: return false;
    }
  };
  def.translation = [](int j, double t, glm::dvec3* tr) {
    if (j != kPelvis) return false;
    *tr = restOffset(kPelvis) + glm::dvec3(0, 0.005 * std::sin(2 * kPi * t / 3.0), 0);
    return true;
  };
  return def;
}

ClipDef waveClip() {
  ClipDef def = clipHeader("wave", 2.5, LoopMode::kOnce, 26);
  def.step_joint = kRHand;
  def.rotation = [](int j, double t, glm::dquat* q) {
    // Raise in the first 0.8 s, wave, lower in the last 0.7 s; ends at the rest pose.
    const double env = smoothstep(0.0, 0.8, t) * (1.0 - smoothstep(1.8, 2.5, t));
    switch (j) {
      case kRUpperArm: *q = axisAngle(-2.5 * env, kZ); return true;
      case kRForearm: *q = axisAngle(env * (-0.4 + 0.35 * std::sin(2 * kPi * 1.2 * t)), kZ); return true;
      case kRHand: *q = axisAngle(env * (std::fmod(t, 0.4) < 0.2 ? 0.3 : -0.3), kY); return true;
      case kHead: *q = axisAngle(-0.25 * env, kY); return true;
      default: return false;
    }
  };
  return def;
}

}  // namespace

std::vector<Clip> defaultClips(bool moving_clips) {
  std::vector<Clip> clips;
  clips.push_back(buildClip(idleClip()));
  clips.push_back(buildClip(
      gaitClip("walk", {1.0, 0.45, 0.1, 0.5, 0.35, 0.25, 0.04, 0.02, 0.08}, 25,
               Interpolation::kLinear)));  // walk_forward's gait too (below).
  clips.push_back(buildClip(
      gaitClip("run", {0.66, 0.8, 0.2, 1.0, 0.6, 1.1, 0.18, 0.04, 0.12}, 9,
               Interpolation::kCubicSpline)));
  clips.push_back(buildClip(waveClip()));
  if (moving_clips) {
    const Gait walk = {1.0, 0.45, 0.1, 0.5, 0.35, 0.25, 0.04, 0.02, 0.08};
    clips.push_back(buildClip(travelingClip(
        "walk_forward", gaitClip("", walk, 25, Interpolation::kLinear), 1.3, 0.0)));
    clips.push_back(buildClip(travelingClip(
        "walk_turn_left", gaitClip("", walk, 25, Interpolation::kLinear), 1.0, kPi / 4)));
    for (size_t i = clips.size() - 2; i < clips.size(); ++i) clips[i].root_motion.extract = true;
  }

  return clips;
}

}  // namespace si::detail::embedded
