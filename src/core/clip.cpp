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

// Interpolation, key times and value count of a track with `values_per_key` values per key
// (three times that for CUBICSPLINE).
Status validateKeys(Interpolation interp, const std::vector<float>& times, size_t value_count,
                    size_t values_per_key, const std::string& where, float duration) {
  if (interp != Interpolation::kDefault && interp != Interpolation::kLinear &&
      interp != Interpolation::kStep && interp != Interpolation::kCubicSpline)
    return {StatusCode::kInvalidArgument,
            strCat(where, ": unknown interpolation ", static_cast<int>(interp))};
  const size_t keys = times.size();
  const size_t per_key = (interp == Interpolation::kCubicSpline ? 3 : 1) * values_per_key;
  if (value_count != keys * per_key)
    return {
        StatusCode::kCountMismatch,
        strCat(where, ": ", value_count, " values for ", keys, " keys (",
               interpolationName(resolveInterpolation(interp)), " needs ", per_key, " per key)")};
  for (size_t k = 0; k < keys; ++k) {
    const float t = times[k];
    if (!std::isfinite(t))
      return {StatusCode::kNotFinite, strCat(where, ": key time ", k, " is not finite")};
    if (t < 0.0f)
      return {StatusCode::kOutOfRange, strCat(where, ": key time ", k, " is negative (", t, ")")};
    if (k > 0 && !(t > times[k - 1]))
      return {StatusCode::kNotSorted, strCat(where, ": key times not increasing at key ", k)};
    if (t > duration)
      return {StatusCode::kOutOfRange, strCat(where, ": key time ", k, " (", t,
                                              " s) is after the clip duration (", duration, " s)")};
  }
  return Status::ok();
}

template <typename T>
Status validateTrack(const Track<T>& track, const std::string& where, float duration) {
  const Status s = validateKeys(track.interpolation, track.times_seconds, track.values.size(), 1,
                                where, duration);
  if (!s.isOk()) return s;
  const size_t per_key = track.interpolation == Interpolation::kCubicSpline ? 3 : 1;
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

Status validateMorphTracks(const std::vector<MorphWeightTrack>& tracks, size_t target_count,
                           const std::string& clip, float duration) {
  std::vector<uint8_t> covered(std::min(target_count, kMaxMorphTargets), 0);
  for (size_t i = 0; i < tracks.size(); ++i) {
    const MorphWeightTrack& t = tracks[i];
    const std::string where = strCat(clip, ": morph track ", i);
    if (t.target_count == 0)
      return {StatusCode::kInvalidArgument, where + ": animates no target (target_count 0)"};
    if (uint64_t(t.first_target) + t.target_count > covered.size())
      return {StatusCode::kOutOfRange, strCat(where, ": targets ", t.first_target, " to ",
                                              uint64_t(t.first_target) + t.target_count - 1,
                                              " pass the ", covered.size(), " targets")};
    for (uint32_t k = t.first_target; k < t.first_target + t.target_count; ++k) {
      if (covered[k])
        return {StatusCode::kInvalidArgument,
                strCat(where, ": target ", k, " is animated by an earlier track too")};
      covered[k] = 1;
    }
    const Status s = validateKeys(t.interpolation, t.times_seconds, t.values.size(), t.target_count,
                                  where, duration);
    if (!s.isOk()) return s;
    for (size_t v = 0; v < t.values.size(); ++v)
      if (!std::isfinite(t.values[v]))
        return {StatusCode::kNotFinite, strCat(where, ": value ", v, " is not finite")};
  }
  return Status::ok();
}

}  // namespace

float Clip::lastKeyTime() const {
  float t = 0.0f;
  for (const JointTracks& j : joint_tracks)
    t = std::max({t, lastTime(j.translation), lastTime(j.rotation), lastTime(j.scale)});
  for (const MorphWeightTrack& m : morph_tracks)
    if (!m.times_seconds.empty()) t = std::max(t, m.times_seconds.back());
  return t;
}

Status Clip::validate(size_t joint_count, size_t morph_target_count) const {
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
  const Status s = validateMorphTracks(morph_tracks, morph_target_count, clip, duration_seconds);
  if (!s.isOk()) return s;
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
