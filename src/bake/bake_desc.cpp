// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/bake/bake_desc.h"

#include <algorithm>
#include <cmath>

#include "bake/key_frames.h"
#include "core/str_cat.h"

namespace si {
using detail::strCat;

const char* interpolationChoiceName(InterpolationChoice c) {
  switch (c) {
    case InterpolationChoice::kDefault: return "default";
    case InterpolationChoice::kLinear: return "linear";
    case InterpolationChoice::kCubic: return "cubic";
    case InterpolationChoice::kSmaller: return "smaller";
  }
  return "invalid";
}

const char* framePlacementName(FramePlacement p) {
  switch (p) {
    case FramePlacement::kDefault: return "default";
    case FramePlacement::kFewer: return "fewer";
    case FramePlacement::kGrid: return "grid";
    case FramePlacement::kKeys: return "keys";
  }
  return "invalid";
}

BakeDesc resolveDefaults(const BakeDesc& desc) {
  BakeDesc d = desc;
  if (d.placement == FramePlacement::kDefault) d.placement = FramePlacement::kFewer;
  if (d.interpolation == InterpolationChoice::kDefault) d.interpolation = InterpolationChoice::kLinear;
  d.format = resolvePaletteFormat(d.format);
  if (d.rate_mode == RateMode::kDefault) d.rate_mode = RateMode::kAutomatic;
  if (d.sample_rate_hz == 0.0f) d.sample_rate_hz = 30.0f;
  if (d.error_tolerance_ratio == 0.0f) d.error_tolerance_ratio = 1e-4f;
  if (d.max_sample_rate_hz == 0.0f) d.max_sample_rate_hz = 240.0f;
  if (d.shell_distance_ratio == 0.0f) d.shell_distance_ratio = 0.05f;
  if (d.joint_stride_texels == 0) d.joint_stride_texels = texelsPerJoint(d.format) == 3 ? 4 : 2;
  if (d.max_texture_size == 0) d.max_texture_size = 16384;
  if (d.max_palette_bytes == 0) d.max_palette_bytes = uint64_t(512) << 20;
  if (d.max_evaluations == 0) d.max_evaluations = uint64_t(1) << 33;
  return d;
}

FramePlan planFrames(double duration_seconds, double rate_hz) {
  FramePlan p;
  if (!(duration_seconds > 0.0) || !(rate_hz > 0.0)) return p;
  // A tiny epsilon keeps 1.0 s at 30 Hz at 30 intervals despite rounding in duration * rate.
  const double intervals = std::max(1.0, std::ceil(duration_seconds * rate_hz - 1e-9));
  p.frame_count = static_cast<uint32_t>(std::min(intervals + 1.0, 4294967295.0));
  p.frame_interval_seconds = duration_seconds / intervals;
  return p;
}

std::vector<uint32_t> drawnVertices(const SkinnedMesh& mesh) {
  std::vector<uint8_t> referenced(mesh.vertexCount(), 0);
  for (const SubMesh& sm : mesh.sub_meshes)
    for (const IndexRange& r : sm.lods)
      for (uint64_t i = r.first_index; i < uint64_t(r.first_index) + r.index_count; ++i)
        if (i < mesh.indices.size() && mesh.indices[size_t(i)] < referenced.size())
          referenced[mesh.indices[size_t(i)]] = 1;
  std::vector<uint32_t> vertices;
  for (size_t v = 0; v < referenced.size(); ++v)
    if (referenced[v]) vertices.push_back(static_cast<uint32_t>(v));
  return vertices;
}

std::vector<uint32_t> usedJoints(const Character& character) {
  const SkinnedMesh& mesh = character.mesh;
  std::vector<uint8_t> used(character.skeleton.jointCount(), 0);
  for (uint32_t v : drawnVertices(mesh)) {
    for (size_t k = 0; k < mesh.influenceCount(); ++k) {
      const Influence in = mesh.influence(v, k);
      if (in.weight > 0.0f && in.joint < used.size()) used[in.joint] = 1;
    }
  }
  std::vector<uint32_t> joints;
  for (size_t j = 0; j < used.size(); ++j)
    if (used[j]) joints.push_back(static_cast<uint32_t>(j));
  return joints;
}

namespace {
void stepKeyTimes(Interpolation interpolation, const std::vector<float>& times, double duration,
                  std::vector<double>* out) {
  if (resolveInterpolation(interpolation) != Interpolation::kStep) return;
  for (size_t k = 1; k < times.size(); ++k)
    if (times[k] > 0.0f && times[k] <= duration) out->push_back(times[k]);
}
}  // namespace

namespace {
// The most frames a clip is baked in (planPalette refuses more by name). A plan past it keeps
// its count alone: its frames are never listed (a key at 1e38 s would list billions).
constexpr uint32_t kMaxPlannedFrames = 1u << 20;

FramePlan planStepFrames(const Clip& clip, double rate_hz) {
  FramePlan plan = planFrames(clip.duration_seconds, rate_hz);
  std::vector<double> steps;
  for (const JointTracks& jt : clip.joint_tracks) {
    stepKeyTimes(jt.translation.interpolation, jt.translation.times_seconds, clip.duration_seconds,
                 &steps);
    stepKeyTimes(jt.rotation.interpolation, jt.rotation.times_seconds, clip.duration_seconds,
                 &steps);
    stepKeyTimes(jt.scale.interpolation, jt.scale.times_seconds, clip.duration_seconds, &steps);
  }
  for (const MorphWeightTrack& m : clip.morph_tracks)
    stepKeyTimes(m.interpolation, m.times_seconds, clip.duration_seconds, &steps);
  if (steps.empty() || plan.frame_count < 2 || plan.frame_count > kMaxPlannedFrames) return plan;
  std::sort(steps.begin(), steps.end());
  steps.erase(std::unique(steps.begin(), steps.end()), steps.end());
  const double dt = plan.frame_interval_seconds, eps = 1e-6 * dt;
  size_t next_step = 0;
  for (uint32_t f = 0; f < plan.frame_count; ++f) {
    const double t = f + 1 == plan.frame_count ? double(clip.duration_seconds) : f * dt;
    while (next_step < steps.size() && steps[next_step] < t - eps) {
      plan.frame_times_seconds.insert(plan.frame_times_seconds.end(), 2, steps[next_step]);
      plan.before_step.insert(plan.before_step.end(), {1, 0});
      ++next_step;
    }
    if (next_step < steps.size() && std::fabs(steps[next_step] - t) <= eps) continue;  // Replaced.
    plan.frame_times_seconds.push_back(t);
    plan.before_step.push_back(0);
  }
  for (; next_step < steps.size(); ++next_step) {  // A key on the clip's end.
    plan.frame_times_seconds.insert(plan.frame_times_seconds.end(), 2, steps[next_step]);
    plan.before_step.insert(plan.before_step.end(), {1, 0});
  }
  plan.frame_count = static_cast<uint32_t>(plan.frame_times_seconds.size());
  return plan;
}

// Any track (a joint's Track or a MorphWeightTrack): its keys inside the clip when LINEAR.
template <typename AnyTrack>
void linearKeyTimes(const AnyTrack& track, double duration, std::vector<double>* out) {
  if (track.times_seconds.size() < 2 ||
      resolveInterpolation(track.interpolation) != Interpolation::kLinear)
    return;
  for (float t : track.times_seconds)
    if (t > 0.0f && t < duration) out->push_back(t);
}

// Marks the frame nearest each corner key as a break, or adds a frame there (materializing the
// grid's times first) when none lies within 1e-3 intervals.
void addCornerBreaks(const Clip& clip, FramePlan* plan) {
  const std::vector<double> corners = cornerKeyTimes(clip);
  const double dt = plan->frame_interval_seconds, near = 1e-3 * dt;
  const uint32_t n = plan->frame_count;
  if (n < 2) return;
  // A LINEAR track also turns at the clip's ends (a loop's wrap is a corner too).
  const auto turns = [](const auto& track) {
    return track.times_seconds.size() >= 2 &&
           resolveInterpolation(track.interpolation) == Interpolation::kLinear;
  };
  bool linear_track = false;
  for (const JointTracks& jt : clip.joint_tracks)
    linear_track = linear_track || turns(jt.translation) || turns(jt.rotation) || turns(jt.scale);
  if (!linear_track) return;
  std::vector<double> times = plan->frame_times_seconds;
  if (times.empty()) {
    for (uint32_t f = 0; f < n; ++f)
      times.push_back(f + 1 == n ? double(clip.duration_seconds) : f * dt);
  }
  std::vector<uint8_t> before = plan->before_step, breaks = plan->breaks;
  before.resize(times.size(), 0);
  breaks.resize(times.size(), 0);
  bool added = false;
  for (double k : corners) {
    const size_t at = size_t(std::lower_bound(times.begin(), times.end(), k) - times.begin());
    size_t nearest = at < times.size() ? at : times.size() - 1;
    if (at > 0 && (at == times.size() || k - times[at - 1] < times[at] - k)) nearest = at - 1;
    if (std::fabs(times[nearest] - k) <= near) {
      breaks[nearest] = 1;
      if (nearest + 1 < times.size() && times[nearest + 1] == times[nearest])
        breaks[nearest + 1] = 1;  // Both frames of a STEP key there.
      continue;
    }
    times.insert(times.begin() + std::ptrdiff_t(at), k);
    before.insert(before.begin() + std::ptrdiff_t(at), 0);
    breaks.insert(breaks.begin() + std::ptrdiff_t(at), 1);
    added = true;
  }
  breaks.front() = breaks.back() = 1;
  if (added || !plan->frame_times_seconds.empty()) {
    plan->frame_times_seconds = std::move(times);
    plan->before_step = std::move(before);
    plan->frame_count = static_cast<uint32_t>(plan->frame_times_seconds.size());
  }
  plan->breaks = std::move(breaks);
}
}  // namespace

std::vector<double> cornerKeyTimes(const Clip& clip) {
  std::vector<double> keys;
  for (const JointTracks& jt : clip.joint_tracks) {
    linearKeyTimes(jt.translation, clip.duration_seconds, &keys);
    linearKeyTimes(jt.rotation, clip.duration_seconds, &keys);
    linearKeyTimes(jt.scale, clip.duration_seconds, &keys);
  }
  for (const MorphWeightTrack& m : clip.morph_tracks)
    linearKeyTimes(m, clip.duration_seconds, &keys);
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

double cornerKeyRate(const Clip& clip) {
  const std::vector<double> keys = cornerKeyTimes(clip);
  const double duration = clip.duration_seconds;
  if (keys.empty() || !(duration > 0.0)) return 0.0;
  double spacing = keys[0];
  for (size_t i = 1; i < keys.size(); ++i) spacing = std::min(spacing, keys[i] - keys[i - 1]);
  spacing = std::min(spacing, duration - keys.back());
  if (!(spacing > 1e-6)) return 0.0;
  const auto whole = [&](double t) {
    return std::fabs(t / spacing - std::round(t / spacing)) <= 1e-3;
  };
  if (!whole(duration)) return 0.0;
  for (double k : keys)
    if (!whole(k)) return 0.0;
  // The grid's own spacing: the duration over a whole number of steps.
  return std::round(duration / spacing) / duration;
}

FramePlan planClipFrames(const Clip& clip, double rate_hz, bool breaks_at_corners) {
  FramePlan plan = planStepFrames(clip, rate_hz);
  if (!plan.frame_times_seconds.empty()) {  // Both frames of each STEP key break the curve.
    plan.breaks.assign(plan.frame_count, 0);
    for (size_t f = 0; f + 1 < plan.before_step.size(); ++f)
      if (plan.before_step[f]) plan.breaks[f] = plan.breaks[f + 1] = 1;
  }
  if (breaks_at_corners && plan.frame_count <= kMaxPlannedFrames) addCornerBreaks(clip, &plan);
  return plan;
}

namespace {
// planPalette(), or with `given` (one plan per selected clip) the frames as given.
Status planPaletteImpl(const Character& character, const BakeDesc& in_desc, PalettePlan* out,
                       Span<const double> clip_rates_hz,
                       Span<const FrameInterpolation> clip_interpolations,
                       const std::vector<FramePlan>* given) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "planPalette: out is null"};
  const BakeDesc d = resolveDefaults(in_desc);
  if (!std::isfinite(d.sample_rate_hz) || d.sample_rate_hz <= 0.0f)
    return {StatusCode::kInvalidArgument, "BakeDesc.sample_rate_hz must be finite and positive"};
  if (d.rate_mode != RateMode::kFixed && d.rate_mode != RateMode::kAutomatic)
    return {StatusCode::kInvalidArgument, "BakeDesc.rate_mode is not a known RateMode"};
  if (d.placement != FramePlacement::kFewer && d.placement != FramePlacement::kGrid &&
      d.placement != FramePlacement::kKeys)
    return {StatusCode::kInvalidArgument, "BakeDesc.placement is not a known FramePlacement"};
  if (!std::isfinite(d.error_tolerance_ratio) || d.error_tolerance_ratio <= 0.0f)
    return {StatusCode::kInvalidArgument, "BakeDesc.error_tolerance_ratio must be positive"};
  if (!std::isfinite(d.max_sample_rate_hz) || d.max_sample_rate_hz <= 0.0f)
    return {StatusCode::kInvalidArgument, "BakeDesc.max_sample_rate_hz must be positive"};
  if (!std::isfinite(d.shell_distance_ratio) || d.shell_distance_ratio <= 0.0f)
    return {StatusCode::kInvalidArgument, "BakeDesc.shell_distance_ratio must be positive"};
  if (d.format != PaletteFormat::kMatrix3x4F32 && d.format != PaletteFormat::kMatrix3x4F16 &&
      d.format != PaletteFormat::kQuatTranslationF32)
    return {StatusCode::kInvalidArgument, "BakeDesc.format is not a known PaletteFormat"};
  if (d.interpolation != InterpolationChoice::kLinear &&
      d.interpolation != InterpolationChoice::kCubic &&
      d.interpolation != InterpolationChoice::kSmaller)
    return {StatusCode::kInvalidArgument,
            "BakeDesc.interpolation is not a known InterpolationChoice"};

  PalettePlan plan;
  if (d.clip_names.empty()) {
    for (size_t c = 0; c < character.clips.size(); ++c)
      plan.clip_indices.push_back(static_cast<uint32_t>(c));
  } else {
    for (const std::string& name : d.clip_names) {
      const int32_t c = character.findClip(name);
      if (c < 0) return {StatusCode::kNotFound, strCat("bake: no clip named '", name, "'")};
      plan.clip_indices.push_back(static_cast<uint32_t>(c));
    }
  }
  if (plan.clip_indices.empty())
    return {StatusCode::kInvalidArgument,
            "bake: the character has no clips to bake (si::makeRestPoseClip gives it its rest "
            "pose as one)"};
  if (!clip_rates_hz.empty() && clip_rates_hz.size() != plan.clip_indices.size())
    return {StatusCode::kInvalidArgument,
            strCat("bake: ", clip_rates_hz.size(), " clip rates for ", plan.clip_indices.size(),
                   " clips")};
  if (!clip_interpolations.empty() && clip_interpolations.size() != plan.clip_indices.size())
    return {StatusCode::kInvalidArgument,
            strCat("bake: ", clip_interpolations.size(), " clip interpolations for ",
                   plan.clip_indices.size(), " clips")};
  bool any_cubic = false;
  for (size_t i = 0; i < plan.clip_indices.size(); ++i) {
    const FrameInterpolation fi =
        !clip_interpolations.empty() ? clip_interpolations[i]
        : d.interpolation == InterpolationChoice::kLinear ? FrameInterpolation::kLinear
                                                          : FrameInterpolation::kCubic;
    if (fi != FrameInterpolation::kLinear && fi != FrameInterpolation::kCubic)
      return {StatusCode::kInvalidArgument,
              strCat("bake: clip interpolation ", i, " is not a known FrameInterpolation")};
    plan.interpolations.push_back(fi);
    any_cubic = any_cubic || fi == FrameInterpolation::kCubic;
  }
  std::vector<uint32_t> frame_counts;
  for (size_t i = 0; i < plan.clip_indices.size(); ++i) {
    const Clip& clip = character.clips[plan.clip_indices[i]];
    const double rate = clip_rates_hz.empty() ? double(d.sample_rate_hz) : clip_rates_hz[i];
    if (!std::isfinite(rate) || rate <= 0.0)
      return {StatusCode::kInvalidArgument, strCat("bake: clip '", clip.name, "' rate ", rate,
                                                   " Hz must be finite and positive")};
    if (given != nullptr && given->size() != plan.clip_indices.size())
      return {StatusCode::kCountMismatch, strCat("bake: ", given->size(), " frame plans for ",
                                                 plan.clip_indices.size(), " clips")};
    const FramePlan f =
        given != nullptr ? (*given)[i]
                         : planClipFrames(clip, rate, plan.interpolations[i] == FrameInterpolation::kCubic);
    if (f.frame_count > kMaxPlannedFrames)
      return {StatusCode::kLimitExceeded, strCat("bake: clip '", clip.name, "' would need ",
                                                 f.frame_count, " frames (at most 2^20)")};
    plan.frames.push_back(f);
    frame_counts.push_back(f.frame_count);
  }
  plan.palette_joints = usedJoints(character);
  if (plan.palette_joints.empty())
    return {StatusCode::kInvalidArgument, "bake: no vertex is weighted to any joint"};
  PaletteLayoutDesc ld;
  ld.joint_count = static_cast<uint32_t>(plan.palette_joints.size());
  ld.clip_frame_counts = frame_counts;
  ld.texels_per_joint = texelsPerJoint(d.format);
  ld.joint_stride_texels = d.joint_stride_texels;
  ld.max_texture_size = d.max_texture_size;
  ld.border_frames = any_cubic ? 1 : 0;
  ld.morph_target_count = uint32_t(character.mesh.morph_targets.size());
  Status s = computePaletteLayout(ld, &plan.layout);
  if (!s.isOk()) return s;
  plan.texture_bytes = plan.layout.textureTexelCount() * bytesPerTexel(d.format);
  if (plan.texture_bytes > d.max_palette_bytes)
    return {StatusCode::kLimitExceeded,
            strCat("bake: the palette would take ", plan.texture_bytes, " bytes (",
                   plan.layout.width, " x ", plan.layout.height, " texels), more than ",
                   "BakeDesc.max_palette_bytes ", d.max_palette_bytes)};
  uint64_t frames = 0;
  for (const FramePlan& f : plan.frames) frames += f.frame_count;
  const uint64_t per_frame = character.skeleton.jointCount() + drawnVertices(character.mesh).size();
  if (frames * per_frame > d.max_evaluations)
    return {StatusCode::kLimitExceeded,
            strCat("bake: ", frames, " frames x (", character.skeleton.jointCount(), " joints + ",
                   per_frame - character.skeleton.jointCount(), " vertices) = ",
                   frames * per_frame, " evaluations, more than BakeDesc.max_evaluations ",
                   d.max_evaluations)};
  *out = std::move(plan);
  return Status::ok();
}

}  // namespace

Status planPalette(const Character& character, const BakeDesc& desc, PalettePlan* out,
                   Span<const double> clip_rates_hz,
                   Span<const FrameInterpolation> clip_interpolations) {
  return planPaletteImpl(character, desc, out, clip_rates_hz, clip_interpolations, nullptr);
}

namespace detail {
Status planPaletteWithFrames(const Character& character, const BakeDesc& desc,
                             const std::vector<FramePlan>& frames,
                             Span<const FrameInterpolation> clip_interpolations,
                             PalettePlan* out) {
  return planPaletteImpl(character, desc, out, {}, clip_interpolations, &frames);
}
}  // namespace detail

}  // namespace si
