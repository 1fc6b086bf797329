// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "bake/key_frames.h"

#include <algorithm>
#include <cmath>

namespace si::detail {

namespace {

void addKeyTimes(Interpolation interpolation, const std::vector<float>& times, double duration,
                 std::vector<double>* keys, std::vector<double>* steps) {
  const bool step = resolveInterpolation(interpolation) == Interpolation::kStep;
  for (size_t k = 0; k < times.size(); ++k) {
    const double t = times[k];
    if (!(t > 0.0) || t > duration) continue;
    if (t < duration) keys->push_back(t);
    if (step && k > 0) steps->push_back(t);  // A STEP track's first key holds from 0.
  }
}

// Every track's keys, joint and morph weight tracks alike.
void addClipKeyTimes(const Clip& clip, double duration, std::vector<double>* keys,
                     std::vector<double>* steps) {
  for (const JointTracks& jt : clip.joint_tracks) {
    addKeyTimes(jt.translation.interpolation, jt.translation.times_seconds, duration, keys, steps);
    addKeyTimes(jt.rotation.interpolation, jt.rotation.times_seconds, duration, keys, steps);
    addKeyTimes(jt.scale.interpolation, jt.scale.times_seconds, duration, keys, steps);
  }
  for (const MorphWeightTrack& m : clip.morph_tracks)
    addKeyTimes(m.interpolation, m.times_seconds, duration, keys, steps);
}

void sortMerged(std::vector<double>* times) {
  std::sort(times->begin(), times->end());
  std::vector<double> merged;
  for (double t : *times)
    if (merged.empty() || t - merged.back() >= 1e-6) merged.push_back(t);
  *times = std::move(merged);
}

std::vector<double> stepTimes(const Clip& clip) {
  std::vector<double> keys, steps;
  addClipKeyTimes(clip, clip.duration_seconds, &keys, &steps);
  sortMerged(&steps);
  return steps;
}

}  // namespace

std::vector<double> keyBreakpoints(const Clip& clip) {
  const double duration = clip.duration_seconds;
  if (!(duration > 0.0)) return {0.0};
  std::vector<double> keys, steps;
  addClipKeyTimes(clip, duration, &keys, &steps);
  keys.push_back(0.0);
  sortMerged(&keys);
  if (duration - keys.back() < 1e-6 && keys.size() > 1) keys.pop_back();
  keys.push_back(duration);
  return keys;
}

FramePlan framesAtKeys(const Clip& clip, const std::vector<double>& breakpoints,
                       const std::vector<uint32_t>& pieces, bool cubic) {
  FramePlan plan;
  if (breakpoints.size() < 2) return plan;  // One frame.
  const std::vector<double> steps = stepTimes(clip);
  size_t next_step = 0;
  const auto isStep = [&](double t) {
    while (next_step < steps.size() && steps[next_step] < t - 1e-6) ++next_step;
    return next_step < steps.size() && std::fabs(steps[next_step] - t) < 1e-6;
  };
  const auto addFrame = [&](double t, uint8_t before, uint8_t brk) {
    plan.frame_times_seconds.push_back(t);
    plan.before_step.push_back(before);
    plan.breaks.push_back(brk);
  };
  for (size_t i = 0; i + 1 < breakpoints.size(); ++i) {
    const double a = breakpoints[i], b = breakpoints[i + 1];
    if (i > 0 && isStep(a)) {
      addFrame(a, 1, 1);
      addFrame(a, 0, 1);
    } else {
      addFrame(a, 0, cubic || i == 0 ? 1 : 0);
    }
    const uint32_t n = std::max(pieces[i], 1u);
    for (uint32_t k = 1; k < n; ++k) addFrame(a + (b - a) * double(k) / double(n), 0, 0);
  }
  const double end = breakpoints.back();
  if (isStep(end)) {
    addFrame(end, 1, 1);
    addFrame(end, 0, 1);
  } else {
    addFrame(end, 0, 1);
  }
  plan.frame_count = uint32_t(plan.frame_times_seconds.size());
  double widest = 0.0;
  for (size_t f = 1; f < plan.frame_times_seconds.size(); ++f)
    widest = std::max(widest, plan.frame_times_seconds[f] - plan.frame_times_seconds[f - 1]);
  const double intervals = widest > 0.0 ? std::max(1.0, std::floor(end / widest)) : 1.0;
  plan.frame_interval_seconds = end / intervals;
  return plan;
}

}  // namespace si::detail
