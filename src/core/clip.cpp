// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/clip.h"

#include <algorithm>
#include <cmath>

#include "core/str_cat.h"

namespace si {
using detail::strCat;

Interpolation resolveInterpolation(Interpolation i) {
  return i == Interpolation::kDefault ? Interpolation::kLinear : i;
}

const char* interpolationName(Interpolation i) {
  switch (i) {
    case Interpolation::kDefault: return "DEFAULT";
    case Interpolation::kLinear: return "LINEAR";
    case Interpolation::kStep: return "STEP";
    case Interpolation::kCubicSpline: return "CUBICSPLINE";
  }
  return "INVALID";
}

LoopMode resolveLoopMode(LoopMode m) { return m == LoopMode::kDefault ? LoopMode::kOnce : m; }

namespace {

template <typename T>
float lastTime(const Track<T>& t) {
  return t.times_seconds.empty() ? 0.0f : t.times_seconds.back();
}

bool finiteValue(const glm::vec3& v) { return isFinite(v); }
bool finiteValue(const glm::quat& q) { return isFinite(q); }
bool zeroLength(const glm::vec3&) { return false; }
bool zeroLength(const glm::quat& q) { return glm::dot(q, q) == 0.0f; }

template <typename T>
Status validateTrack(const Track<T>& track, const std::string& where, float duration) {
  const Interpolation interp = track.interpolation;
  if (interp != Interpolation::kDefault && interp != Interpolation::kLinear &&
      interp != Interpolation::kStep && interp != Interpolation::kCubicSpline)
    return {StatusCode::kInvalidArgument,
            strCat(where, ": unknown interpolation ", static_cast<int>(interp))};
  const size_t keys = track.times_seconds.size();
  const size_t per_key = interp == Interpolation::kCubicSpline ? 3 : 1;
  if (track.values.size() != keys * per_key)
    return {StatusCode::kCountMismatch,
            strCat(where, ": ", track.values.size(), " values for ", keys, " keys (",
                   interpolationName(resolveInterpolation(interp)), " needs ", per_key,
                   " per key)")};
  for (size_t k = 0; k < keys; ++k) {
    const float t = track.times_seconds[k];
    if (!std::isfinite(t))
      return {StatusCode::kNotFinite, strCat(where, ": key time ", k, " is not finite")};
    if (t < 0.0f)
      return {StatusCode::kOutOfRange, strCat(where, ": key time ", k, " is negative (", t, ")")};
    if (k > 0 && !(t > track.times_seconds[k - 1]))
      return {StatusCode::kNotSorted, strCat(where, ": key times not increasing at key ", k)};
    if (t > duration)
      return {StatusCode::kOutOfRange, strCat(where, ": key time ", k, " (", t,
                                              " s) is after the clip duration (", duration, " s)")};
  }
  for (size_t v = 0; v < track.values.size(); ++v) {
    if (!finiteValue(track.values[v]))
      return {StatusCode::kNotFinite, strCat(where, ": value ", v, " is not finite")};
    const bool is_key_value = per_key == 1 || v % 3 == 1;
    if (is_key_value && zeroLength(track.values[v]))
      return {StatusCode::kInvalidArgument,
              strCat(where, ": rotation key ", v / per_key, " has zero length")};
  }
  return Status::ok();
}

}  // namespace

float Clip::lastKeyTime() const {
  float t = 0.0f;
  for (const JointTracks& j : joint_tracks)
    t = std::max({t, lastTime(j.translation), lastTime(j.rotation), lastTime(j.scale)});
  return t;
}

Status Clip::validate(size_t joint_count) const {
  const std::string clip = strCat("clip '", name, "'");
  if (joint_tracks.size() != joint_count)
    return {StatusCode::kCountMismatch, strCat(clip, ": ", joint_tracks.size(),
                                               " joint tracks for a skeleton of ", joint_count,
                                               " joints")};
  if (!std::isfinite(duration_seconds))
    return {StatusCode::kNotFinite, clip + ": duration is not finite"};
  if (duration_seconds < 0.0f)
    return {StatusCode::kOutOfRange, clip + ": duration is negative"};
  if (loop_mode != LoopMode::kDefault && loop_mode != LoopMode::kOnce &&
      loop_mode != LoopMode::kLoop)
    return {StatusCode::kInvalidArgument,
            strCat(clip, ": unknown loop mode ", static_cast<int>(loop_mode))};
  for (size_t j = 0; j < joint_tracks.size(); ++j) {
    const JointTracks& jt = joint_tracks[j];
    const std::string joint = strCat(clip, ": joint ", j);
    Status s = validateTrack(jt.translation, joint + " translation", duration_seconds);
    if (s.isOk()) s = validateTrack(jt.rotation, joint + " rotation", duration_seconds);
    if (s.isOk()) s = validateTrack(jt.scale, joint + " scale", duration_seconds);
    if (!s.isOk()) return s;
  }
  return validateMarkers(markers, duration_seconds, clip + ": ");
}

Status validateMarkers(const std::vector<AnimationMarker>& markers, double duration,
                       const std::string& where) {
  for (size_t i = 0; i < markers.size(); ++i) {
    const AnimationMarker& m = markers[i];
    const std::string what = strCat(where, "marker ", i, " '", m.name, "'");
    if (!std::isfinite(m.time_seconds)) return {StatusCode::kNotFinite, what + ": time is not finite"};
    if (m.time_seconds < 0.0 || m.time_seconds > duration)
      return {StatusCode::kOutOfRange, strCat(what, ": time ", m.time_seconds,
                                              " s is outside the clip's [0, ", duration, "] s")};
    if (m.name.empty()) return {StatusCode::kInvalidArgument, what + ": the name is empty"};
  }
  return Status::ok();
}

Clip makeRestPoseClip(size_t joint_count, const std::string& name) {
  Clip c;
  c.name = name;
  c.duration_seconds = 0.0f;
  c.loop_mode = LoopMode::kOnce;
  c.joint_tracks.resize(joint_count);
  return c;
}

}  // namespace si
