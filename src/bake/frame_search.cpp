// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The automatic mode's frame search (see frame_search.h).
#include "bake/frame_search.h"

#include <algorithm>
#include <cmath>

#include "bake/clip_measurement.h"
#include "bake/key_frames.h"
#include "bake/palette_texels.h"

namespace si::detail {

namespace {

// Candidate grid rates, lowest first.
const double kCandidateRates[] = {5, 10, 15, 20, 24, 30, 40, 48, 60, 80, 96, 120, 160, 240};

// Key placement may divide a key interval up to this many times the grid's highest rate.
constexpr double kKeyRateFactor = 4.0;

// Most rounds of dividing key intervals; each costs a trial on the subset.
constexpr int kKeyRounds = 12;

// Per key interval, the largest of `interval_errors` (per frame interval of `frames`): each
// frame interval belongs to the key interval holding its midpoint.
std::vector<double> keyIntervalErrors(const FramePlan& frames, const std::vector<double>& breakpoints,
                                      const std::vector<double>& interval_errors) {
  std::vector<double> out(breakpoints.size() - 1, 0.0);
  const std::vector<double>& t = frames.frame_times_seconds;
  for (size_t j = 0; j < interval_errors.size() && j + 1 < t.size(); ++j) {
    const double mid = 0.5 * (t[j] + t[j + 1]);
    size_t k = size_t(std::upper_bound(breakpoints.begin(), breakpoints.end(), mid) - breakpoints.begin());
    k = std::min(std::max<size_t>(k, 1), out.size()) - 1;
    out[k] = std::max(out[k], interval_errors[j]);
  }
  return out;
}

// Divides further every key interval whose error is above `target`: by the error's ratio to
// the power 1/2 (linear) or 1/4 (cubic, from 3 pieces), at least one more piece, at most `cap`.
bool divideWhereMissed(const std::vector<double>& key_errors, double target, bool cubic,
                       const std::vector<uint32_t>& cap, std::vector<uint32_t>* pieces) {
  bool changed = false;
  for (size_t i = 0; i < pieces->size(); ++i) {
    uint32_t& p = (*pieces)[i];
    if (!(key_errors[i] > target) || p >= cap[i]) continue;
    // Cubic below 3 pieces is linear or quadratic: growing by their order overshoots, so an
    // interval that misses goes to 3, the fewest a Catmull-Rom interval needs.
    const double grown =
        cubic ? (p < 3 ? 3.0 : std::ceil(double(p) * std::pow(key_errors[i] / target, 0.25) * 1.05))
              : std::ceil(double(p) * std::sqrt(key_errors[i] / target) * 1.05);
    p = uint32_t(std::min<double>(std::max<double>(grown, p + 1.0), cap[i]));
    changed = true;
  }
  return changed;
}

}  // namespace

bool betterChoice(const FrameChoice& b, const FrameChoice& a, double target) {
  const bool a_met = a.subset_error <= target, b_met = b.subset_error <= target;
  if (a_met != b_met) return b_met;
  if (a.frames.frame_count != b.frames.frame_count)
    return b.frames.frame_count < a.frames.frame_count;
  return b.subset_error < a.subset_error;
}

FrameSearch::FrameSearch(const Character& character, const BakeDesc& desc,
                         const SkinnedMesh& gpu_mesh, const std::vector<uint32_t>& picked)
    : character_(character), desc_(desc) {
  search_mesh_ = subsetMesh(character.mesh, picked);
  search_gpu_mesh_ = subsetMesh(gpu_mesh, picked);
  search_vertices_.resize(search_mesh_.vertexCount());
  for (size_t i = 0; i < search_vertices_.size(); ++i) search_vertices_[i] = uint32_t(i);
  for (double r : kCandidateRates)
    if (r <= desc.max_sample_rate_hz) candidates_.push_back(r);
  if (candidates_.empty() || candidates_.back() < desc.max_sample_rate_hz)
    candidates_.push_back(desc.max_sample_rate_hz);
  const double height = character.height() > 0.0f ? character.height() : 1.0;
  shell_ = desc.shell_distance_ratio * height;
  tolerance_ = desc.error_tolerance_ratio * height;
}

Status FrameSearch::trial(const Clip& clip, FrameInterpolation interpolation,
                          const FramePlan& frames, double* error,
                          std::vector<double>* interval_errors) const {
  BakeDesc one = desc_;
  one.clip_names = {clip.name};
  one.rate_mode = RateMode::kFixed;
  const FrameInterpolation interpolations[] = {interpolation};
  PalettePlan plan;
  BakedPalette palette;
  ClipErrorReport m;
  Status s = planPaletteWithFrames(character_, one, {frames}, interpolations, &plan);
  if (s.isOk()) s = bakeTexels(character_, one, plan, &palette);
  if (s.isOk())
    s = measureClip(character_, search_mesh_, search_gpu_mesh_, palette, 0, search_vertices_,
                    shell_, true, &m, interval_errors);
  *error = m.max_error_units;
  return s;
}

Status FrameSearch::gridChoice(const Clip& clip, FrameInterpolation interpolation, double target,
                               FrameChoice* out) const {
  std::vector<double> candidates = candidates_;
  const bool cubic = interpolation == FrameInterpolation::kCubic;
  // A cubic clip whose corner keys lie on a grid: the multiples of its rate, so that frames
  // land on the corners (between them the curve is smooth and the spline converges fast).
  const double key_rate = cubic ? cornerKeyRate(clip) : 0.0;
  if (key_rate > 0.0 && key_rate <= desc_.max_sample_rate_hz) {
    candidates.clear();
    for (double m = 1.0; m * key_rate <= desc_.max_sample_rate_hz * (1.0 + 1e-9); m += 1.0)
      candidates.push_back(m * key_rate);
  }
  // If a choice exists, keep refining from it (refine() steps to the next rate).
  size_t lo = 0, hi = candidates.size() - 1;
  if (out->rate_hz > 0.0 && !out->at_keys) {
    while (lo < hi && candidates[lo] <= out->rate_hz) ++lo;
    hi = lo;
  }
  std::vector<double> errors(candidates.size(), -1.0);  // Trials made, by candidate.
  while (lo < hi) {  // The lowest candidate meeting the target (error falls as the rate rises).
    const size_t mid = (lo + hi) / 2;
    Status s = trial(clip, interpolation, planClipFrames(clip, candidates[mid], cubic),
                     &errors[mid], nullptr);
    if (!s.isOk()) return s;
    if (errors[mid] <= target) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  FrameChoice c;
  c.interpolation = interpolation;
  c.rate_hz = candidates[lo];
  c.frames = planClipFrames(clip, c.rate_hz, cubic);
  c.subset_error = errors[lo];
  Status s = errors[lo] >= 0.0 ? Status::ok()
                               : trial(clip, interpolation, c.frames, &c.subset_error, nullptr);
  c.can_refine = lo + 1 < candidates.size();
  *out = std::move(c);
  return s;
}

std::vector<uint32_t> FrameSearch::maxPieces(const std::vector<double>& breakpoints) const {
  std::vector<uint32_t> cap;
  const double rate = kKeyRateFactor * desc_.max_sample_rate_hz;
  for (size_t i = 0; i + 1 < breakpoints.size(); ++i)
    cap.push_back(uint32_t(std::max(1.0, std::min(65536.0, std::ceil((breakpoints[i + 1] - breakpoints[i]) * rate)))));
  return cap;
}

Status FrameSearch::keyChoice(const Clip& clip, FrameInterpolation interpolation, double target,
                              FrameChoice* out) const {
  FrameChoice c;
  c.interpolation = interpolation;
  c.at_keys = true;
  c.breakpoints = keyBreakpoints(clip);
  if (c.breakpoints.size() < 2) return {StatusCode::kInvalidArgument, "key placement: one frame"};
  const bool cubic = interpolation == FrameInterpolation::kCubic;
  const std::vector<uint32_t> cap = maxPieces(c.breakpoints);
  c.pieces.assign(c.breakpoints.size() - 1, 1);
  std::vector<double> interval_errors;
  for (int round = 0; round < kKeyRounds; ++round) {
    c.frames = framesAtKeys(clip, c.breakpoints, c.pieces, cubic);
    Status s = trial(clip, interpolation, c.frames, &c.subset_error, &interval_errors);
    if (!s.isOk()) return s;
    if (!(c.subset_error > target)) break;
    if (!divideWhereMissed(keyIntervalErrors(c.frames, c.breakpoints, interval_errors), target,
                           cubic, cap, &c.pieces))
      break;
  }
  c.can_refine = false;
  for (size_t i = 0; i < c.pieces.size(); ++i) c.can_refine = c.can_refine || c.pieces[i] < cap[i];
  c.rate_hz = clip.duration_seconds > 0.0f ? (c.frames.frame_count - 1) / double(clip.duration_seconds) : 0.0;
  *out = std::move(c);
  return Status::ok();
}

Status FrameSearch::choose(const Clip& clip, FrameInterpolation interpolation,
                           FrameChoice* out) const {
  // A format whose precision floor is above the tolerance (half floats) cannot meet it: then
  // aim for 1.1 x the error at the highest rate instead of climbing to it.
  // The floor is the smaller error of the densest grid and the densest key placement (a grid
  // cuts the corners at keys off it, so its floor can be far above the format's); the key
  // placement's trial is skipped where it would pass the bake's limits.
  const bool cubic = interpolation == FrameInterpolation::kCubic;
  double floor_error = 0.0;
  Status s = trial(clip, interpolation, planClipFrames(clip, candidates_.back(), cubic),
                   &floor_error, nullptr);
  if (!s.isOk()) return s;
  const std::vector<double> breakpoints = keyBreakpoints(clip);
  if (floor_error > tolerance_ && breakpoints.size() >= 2 &&
      desc_.placement != FramePlacement::kGrid) {
    double keys_floor = 0.0;
    if (trial(clip, interpolation, framesAtKeys(clip, breakpoints, maxPieces(breakpoints), cubic),
              &keys_floor, nullptr).isOk())
      floor_error = std::min(floor_error, keys_floor);
  }
  // Only a floor above the tolerance moves the target: one just below it is within reach.
  const double target = floor_error > tolerance_ ? 1.1 * floor_error : tolerance_;
  FrameChoice grid, keys;
  const bool timed = clip.duration_seconds > 0.0f;
  if (!timed || desc_.placement != FramePlacement::kKeys) {
    s = gridChoice(clip, interpolation, target, &grid);
    if (!s.isOk()) return s;
  }
  if (!timed || desc_.placement == FramePlacement::kGrid) {
    *out = std::move(grid);
    out->target = target;
    return Status::ok();
  }
  s = keyChoice(clip, interpolation, target, &keys);
  // Frames at every key may pass the bake's limits (a clip keyed far more densely than it
  // needs) where the grid does not: then the grid, unless only keys were asked for.
  if (s.code() == StatusCode::kLimitExceeded && desc_.placement != FramePlacement::kKeys) {
    *out = std::move(grid);
    out->target = target;
    return Status::ok();
  }
  if (!s.isOk()) return s;
  if (desc_.placement == FramePlacement::kKeys) {
    *out = std::move(keys);
    out->target = target;
    return Status::ok();
  }
  *out = std::move(betterChoice(keys, grid, target) ? keys : grid);
  out->target = target;
  return Status::ok();
}

bool FrameSearch::refine(const Clip& clip, const std::vector<double>& interval_errors,
                         FrameChoice* choice) const {
  const double tolerance = choice->target;
  if (!choice->can_refine) return false;
  const bool cubic = choice->interpolation == FrameInterpolation::kCubic;
  if (choice->at_keys) {
    const std::vector<uint32_t> cap = maxPieces(choice->breakpoints);
    if (!divideWhereMissed(keyIntervalErrors(choice->frames, choice->breakpoints, interval_errors),
                           tolerance, cubic, cap, &choice->pieces))
      return false;
    choice->frames = framesAtKeys(clip, choice->breakpoints, choice->pieces, cubic);
    choice->can_refine = false;
    for (size_t i = 0; i < choice->pieces.size(); ++i)
      choice->can_refine = choice->can_refine || choice->pieces[i] < cap[i];
    choice->rate_hz = (choice->frames.frame_count - 1) / double(clip.duration_seconds);
    return true;
  }
  FrameChoice next = *choice;
  if (!gridChoice(clip, choice->interpolation, 0.0, &next).isOk() || next.rate_hz <= choice->rate_hz)
    return false;
  next.target = choice->target;
  *choice = std::move(next);
  return true;
}

}  // namespace si::detail
