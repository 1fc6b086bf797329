// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The AnimationBaker: clips to palette texels, with an error report measured by emulating the
// shader against the double-precision reference. Technique: B. Dudash, "Skinned Instancing",
// NVIDIA whitepaper (2007), and GPU Gems 3 ch. 2; the shell error metric follows N. Frechette's
// Animation Compression Library (docs/error_metrics.md).
#include "si/bake/animation_baker.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "bake/clip_measurement.h"
#include "bake/frame_search.h"
#include "bake/joint_bounds.h"
#include "bake/key_frames.h"
#include "bake/palette_texels.h"
#include "core/box_sphere.h"
#include "core/str_cat.h"
#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"

namespace si {
using detail::strCat;

Status bakePalette(const Character& character, const BakeDesc& in_desc, BakedPalette* palette,
                   BakeReport* report) {
  if (palette == nullptr) return {StatusCode::kInvalidArgument, "bakePalette: palette is null"};
  Status s = character.validate();
  if (!s.isOk()) return s;
  const BakeDesc d = resolveDefaults(in_desc);
  PalettePlan plan;
  s = planPalette(character, d, &plan);
  if (!s.isOk()) return s;
  const double height = character.height() > 0.0f ? character.height() : 1.0;
  const double shell = d.shell_distance_ratio * height;
  const std::vector<uint32_t> vertices = drawnVertices(character.mesh);
  // Measure what the GPU draws: the vertex format stores weights as unorm16 (si::gl).
  const SkinnedMesh gpu_mesh = detail::storedWeightsMesh(character.mesh);

  const uint32_t clip_count = static_cast<uint32_t>(plan.clip_indices.size());
  // Automatic rates: the search takes about 60 % of the time, the final measurement the rest.
  const bool automatic = d.rate_mode == RateMode::kAutomatic;
  const double search_share = automatic ? 0.6 : 0.0;
  const auto progress = [&](const char* stage, uint32_t clip, double fraction) {
    if (d.progress) d.progress(BakeProgress{fraction, stage, clip, clip_count});
  };
  const double tolerance = d.error_tolerance_ratio * height;
  std::vector<detail::FrameChoice> choices(clip_count);
  std::vector<FrameInterpolation> interpolations = plan.interpolations;
  const auto replan = [&]() {
    std::vector<FramePlan> frames;
    for (const detail::FrameChoice& c : choices) frames.push_back(c.frames);
    return detail::planPaletteWithFrames(character, d, frames, interpolations, &plan);
  };
  // The search's subset, and the short list measured at the intervals' other fractions.
  const bool measure = report != nullptr || automatic;
  const std::vector<uint32_t> short_list =
      measure ? detail::searchVertices(character, character.mesh, vertices) : std::vector<uint32_t>{};
  std::unique_ptr<detail::FrameSearch> search;
  if (automatic) {
    // The plan's first frames baked once: a pose the format cannot hold is refused by name
    // (bakeTexels) before the search measures errors that are not numbers.
    BakedPalette probe;
    s = detail::bakeTexels(character, d, plan, &probe);
    if (!s.isOk()) return s;
    search = std::make_unique<detail::FrameSearch>(character, d, gpu_mesh, short_list);
    for (uint32_t c = 0; c < clip_count; ++c) {
      progress("choosing rates", c, search_share * double(c) / clip_count);
      const Clip& clip = character.clips[plan.clip_indices[c]];
      if (d.interpolation == InterpolationChoice::kSmaller) {
        // Both, then: one that meets the tolerance beats one that does not; then fewer
        // frames (linear on a tie: half the reads); then the smaller error.
        detail::FrameChoice linear, cubic;
        s = search->choose(clip, FrameInterpolation::kLinear, &linear);
        if (s.isOk()) s = search->choose(clip, FrameInterpolation::kCubic, &cubic);
        if (!s.isOk()) return s;
        choices[c] = std::move(detail::betterChoice(cubic, linear, tolerance) ? cubic : linear);
      } else {
        s = search->choose(clip, interpolations[c], &choices[c]);
        if (!s.isOk()) return s;
      }
      interpolations[c] = choices[c].interpolation;
    }
    s = replan();
    if (!s.isOk()) return s;
  }

  progress("baking", 0, search_share);
  BakedPalette baked;
  s = detail::bakeTexels(character, d, plan, &baked);
  if (!s.isOk()) return s;

  // The whole mesh, measured once per clip; automatic choices that miss the tolerance there
  // are made denser where they miss and measured again (a few rounds at most).
  std::vector<ClipErrorReport> measured(clip_count);
  std::vector<std::vector<double>> interval_errors(clip_count);
  std::vector<uint8_t> stale(clip_count, measure ? 1 : 0);
  for (int round = 0; measure; ++round) {
    for (uint32_t c = 0; c < clip_count; ++c) {
      if (!stale[c]) continue;
      progress("measuring", c, search_share + (1.0 - search_share) * double(c) / clip_count);
      measured[c] = ClipErrorReport{};
      s = detail::measureClip(character, character.mesh, gpu_mesh, baked, c, vertices, shell,
                              false, &measured[c], &interval_errors[c], &short_list);
      if (!s.isOk()) return s;
      stale[c] = 0;
    }
    if (!automatic || round >= 4) break;
    const std::vector<detail::FrameChoice> before = choices;
    bool refined = false;
    for (uint32_t c = 0; c < clip_count; ++c) {
      if (!(measured[c].max_error_units > choices[c].target)) continue;
      const Clip& clip = character.clips[plan.clip_indices[c]];
      if (search->refine(clip, interval_errors[c], &choices[c])) stale[c] = refined = 1;
    }
    if (!refined) break;
    s = replan();
    if (s.code() == StatusCode::kLimitExceeded) {  // Denser frames pass a limit: keep the last.
      choices = before;
      s = replan();
      if (!s.isOk()) return s;
      break;
    }
    if (s.isOk()) s = detail::bakeTexels(character, d, plan, &baked);
    if (!s.isOk()) return s;
  }

  BakeReport rep;
  for (uint32_t c = 0; c < baked.clips.size(); ++c) {
    ClipErrorReport& m = measured[c];
    Aabb bounds;
    s = detail::clipBounds(baked, c, gpu_mesh, vertices, &bounds);
    if (!s.isOk()) return s;
    // Matrix formats stay within clipBounds() up to float rounding; the rotation format's
    // normalization can bulge, so pad by 1 % of the height.
    const float pad = static_cast<float>(
        height * (d.format == PaletteFormat::kQuatTranslationF32 ? 1e-2 : 1e-5));
    bounds.min -= glm::vec3(pad);
    bounds.max += glm::vec3(pad);
    BakedClip& bc = baked.clips[c];
    // The box's circumsphere contains the mesh; in double, so a mesh spanning most of the float
    // range is refused by name instead of leaving an infinite sphere in the palette.
    double radius = 0.0;
    const Sphere sphere = detail::boxSphere(bounds, &radius);
    const glm::dvec3 lo(bounds.min), hi(bounds.max);
    const double float_max = 3.0e38;
    if (!(std::isfinite(radius) && radius < float_max && glm::all(glm::lessThan(glm::abs(lo),
          glm::dvec3(float_max))) && glm::all(glm::lessThan(glm::abs(hi), glm::dvec3(float_max)))))
      return {StatusCode::kOutOfRange,
              strCat("bake: clip ", c, " '", baked.clips[c].name,
                     "': the skinned mesh spans past what float bounds hold (box from ",
                     lo.x, ", ", lo.y, ", ", lo.z, " to ", hi.x, ", ", hi.y, ", ", hi.z, ")")};
    bc.bounds = bounds;
    bc.bounding_sphere = sphere;
    if (measure) {
      m.interpolation = bc.interpolation;
      m.palette_bytes = (uint64_t(bc.frame_count) + 2 * baked.layout.border_frames) *
                        baked.layout.frame_stride_texels * bytesPerTexel(d.format);
      m.tolerance_met = m.max_error_units <= tolerance;
      if (automatic && choices[c].at_keys) {
        m.frames_at_keys = true;
        m.sample_rate_hz = choices[c].rate_hz;
      }
      rep.max_error_units = std::max(rep.max_error_units, m.max_error_units);
      rep.max_error_ratio = std::max(rep.max_error_ratio, m.max_error_ratio);
      rep.p99_error_units = std::max(rep.p99_error_units, m.p99_error_units);
      rep.clips.push_back(std::move(m));
    }
  }
  if (automatic && !d.accept_tolerance_miss) {
    for (uint32_t c = 0; c < clip_count; ++c) {
      const ClipErrorReport& m = rep.clips[c];
      if (m.tolerance_met) continue;
      const detail::FrameChoice& ch = choices[c];
      const uint32_t joint = m.max_error_joint;
      return {StatusCode::kToleranceNotMet,
              strCat("bake: clip '", m.name, "' misses the tolerance: max error ",
                     m.max_error_units, " units (", m.max_error_ratio, " of the height ", height,
                     ") at t=", m.max_error_time_seconds, " s, vertex ", m.max_error_vertex,
                     ", joint ", joint, " '", joint < character.skeleton.joint_names.size()
                         ? character.skeleton.joint_names[joint] : std::string(),
                     "'; the tolerance is ", d.error_tolerance_ratio, " of the height (",
                     tolerance, " units). Tried ", paletteFormatName(d.format), ", ",
                     ch.interpolation == FrameInterpolation::kCubic ? "cubic" : "linear",
                     ", up to ", d.max_sample_rate_hz, " Hz on a uniform grid and ",
                     4.0 * double(d.max_sample_rate_hz),
                     " Hz within key intervals; chose ", m.frame_count, " frames",
                     ch.at_keys ? " at the keys" : " on a grid",
                     ch.target > tolerance
                         ? strCat("; the densest frames tried reach ", ch.target / 1.1,
                                  " units on the short list: the format's precision bounds it, "
                                  "a finer format may reach it")
                         : std::string("; a higher BakeDesc::max_sample_rate_hz may reach it"),
                     ". BakeDesc::accept_tolerance_miss keeps this bake")};
    }
  }
  baked.joint_bounds = detail::jointBounds(baked, gpu_mesh, vertices);
  if (report != nullptr) {
    rep.palette_bytes = baked.layout.textureTexelCount() * bytesPerTexel(d.format);
    for (size_t j = 0; j < character.skeleton.jointCount(); ++j)
      if (baked.skeleton_to_palette[j] < 0)
        rep.joints_left_out.push_back(character.skeleton.joint_names[j]);
    std::vector<uint32_t> all_frames;
    for (size_t c = 0; c < character.clips.size(); ++c) {
      const auto it = std::find(plan.clip_indices.begin(), plan.clip_indices.end(), uint32_t(c));
      if (it == plan.clip_indices.end()) {
        rep.clips_left_out.push_back(character.clips[c].name);
        all_frames.push_back(
            planFrames(character.clips[c].duration_seconds, d.sample_rate_hz).frame_count);
      } else {
        all_frames.push_back(plan.frames[size_t(it - plan.clip_indices.begin())].frame_count);
      }
    }
    PaletteLayoutDesc full;
    full.joint_count = static_cast<uint32_t>(character.skeleton.jointCount());
    full.clip_frame_counts = all_frames;
    full.texels_per_joint = baked.layout.texels_per_joint;
    full.joint_stride_texels = baked.layout.joint_stride_texels;
    full.morph_target_count = baked.layout.morph_target_count;
    full.max_texture_size = 1u << 30;  // Hypothetical: only its size matters.
    PaletteLayout full_layout;
    if (computePaletteLayout(full, &full_layout).isOk()) {
      const uint64_t full_bytes = full_layout.used_texel_count * bytesPerTexel(d.format);
      const uint64_t used_bytes = baked.layout.used_texel_count * bytesPerTexel(d.format);
      rep.bytes_saved = full_bytes > used_bytes ? full_bytes - used_bytes : 0;
    }
    *report = std::move(rep);
  }
  *palette = std::move(baked);
  progress("measuring", clip_count ? clip_count - 1 : 0, 1.0);
  return Status::ok();
}

}  // namespace si
