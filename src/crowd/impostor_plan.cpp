// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The impostor atlas's plan and capture crowd, shared by both back-ends' buildImpostor.
#include "crowd/impostor_plan.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/str_cat.h"
#include "crowd/view_rotation.h"
#include "si/crowd/handle_pool.h"

namespace si::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The view directions: per elevation, every azimuth.
std::vector<glm::quat> viewRotations(const ImpostorPlan& plan) {
  std::vector<glm::quat> rotations;
  const uint32_t views = plan.info.views;
  for (uint32_t view = 0; view < views; ++view)
    rotations.push_back(viewRotation(plan.elevations_degrees[view / plan.azimuths],
                                     2.0 * kPi * (view % plan.azimuths) / plan.azimuths));
  return rotations;
}

}  // namespace

Status planImpostor(const BakedPalette& palette, uint32_t sub_meshes, const ImpostorDesc& desc,
                    Span<const ImpostorSide> sides, uint32_t max_supersample, const char* call,
                    ImpostorPlan* out) {
  ImpostorPlan plan;
  plan.azimuths = desc.azimuths ? desc.azimuths : 16u;
  plan.elevations_degrees = desc.elevations_degrees.empty() ? std::vector<float>{0.0f, 30.0f, 60.0f}
                                                            : desc.elevations_degrees;
  const uint32_t per_clip = desc.frames_per_clip ? desc.frames_per_clip : 8u;
  plan.cell = desc.cell_pixels ? desc.cell_pixels : 32u;
  const uint32_t all = sub_meshes >= 32 ? 0xFFFFFFFFu : (1u << sub_meshes) - 1u;
  plan.mask = desc.variation_mask ? desc.variation_mask & all : all;
  const std::vector<float>& elevations = plan.elevations_degrees;
  if (elevations.size() > 4)
    return {StatusCode::kInvalidArgument,
            strCat(call, ": ", elevations.size(), " elevations; at most 4")};
  for (size_t k = 0; k < elevations.size(); ++k)
    if (!(elevations[k] >= -90.0f && elevations[k] <= 90.0f) ||
        (k > 0 && !(elevations[k] > elevations[k - 1])))
      return {StatusCode::kInvalidArgument,
              strCat(call, ": elevations must increase, within [-90, 90] degrees")};
  if ((plan.cell & (plan.cell - 1)) != 0)  // Mip level l halves every cell l times.
    return {StatusCode::kInvalidArgument,
            strCat(call, ": cell_pixels ", plan.cell,
                   "; a power of two (each mip level halves every cell, down to one texel)")};
  if (plan.mask == 0)
    return {StatusCode::kInvalidArgument,
            strCat(call, ": variation mask 0x", std::hex, desc.variation_mask,
                   " wears none of the character's sub-meshes")};
  if (!(desc.lod_bias >= -2.0f && desc.lod_bias <= 2.0f))
    return {StatusCode::kInvalidArgument,
            strCat(call, ": lod_bias ", desc.lod_bias, "; within [-2, 2] (mip levels)")};
  const uint32_t asked = desc.capture_supersample;
  if (asked != 0 && asked != 1 && asked != 2 && asked != 4)
    return {StatusCode::kInvalidArgument,
            strCat(call, ": capture_supersample ", asked, "; 0 (automatic), 1, 2 or 4")};
  if (asked > std::max(max_supersample, 1u))
    return {StatusCode::kUnsupported,
            strCat(call, ": capture_supersample ", asked, "; this back-end captures at most ",
                   std::max(max_supersample, 1u), " texels each way per atlas texel")};

  for (size_t k = 0; k < elevations.size(); ++k)
    plan.elevations_radians[k] = float(elevations[k] * kPi / 180.0);

  // The captured frames: per clip, min(frames, baked frames) spread over its baked frames.
  for (uint32_t k = 0; k < palette.clips.size(); ++k) {
    const BakedClip& clip = palette.clips[k];
    const uint32_t n = std::max<uint32_t>(clip.frame_count, 1);
    const uint32_t f = std::min(per_clip, n);
    plan.clips.emplace_back(clip.first_texel, n, uint32_t(plan.frames.size()), f);
    for (uint32_t j = 0; j < f; ++j)
      plan.frames.push_back(
          {k, f > 1 ? uint32_t((uint64_t(j) * (n - 1) + (f - 1) / 2) / (f - 1)) : 0u});
  }
  std::sort(plan.clips.begin(), plan.clips.end(),
            [](const glm::uvec4& a, const glm::uvec4& b) { return a.x < b.x; });
  const uint32_t views = plan.azimuths * uint32_t(elevations.size());
  plan.cells = uint64_t(plan.frames.size()) * views;
  plan.columns = uint32_t(std::ceil(std::sqrt(double(plan.cells))));
  plan.rows = uint32_t((plan.cells + plan.columns - 1) / plan.columns);
  // The plan, reported before anything is allocated, also when refused below.
  const uint64_t width = uint64_t(plan.columns) * plan.cell;
  const uint64_t height = uint64_t(plan.rows) * plan.cell;
  plan.levels = 1;
  while ((plan.cell >> plan.levels) > 0) ++plan.levels;  // Down to one texel a cell.
  ImpostorInfo& info = plan.info;
  info.views = views;
  info.frames = uint32_t(plan.frames.size());
  info.cells = uint32_t(std::min<uint64_t>(plan.cells, UINT32_MAX));
  info.cell_pixels = plan.cell;
  info.width = uint32_t(std::min<uint64_t>(width, UINT32_MAX));
  info.height = uint32_t(std::min<uint64_t>(height, UINT32_MAX));
  for (uint32_t l = 0; l < plan.levels; ++l)
    info.bytes += std::max<uint64_t>(width >> l, 1) * std::max<uint64_t>(height >> l, 1) * 4 * 3;
  const uint64_t budget = desc.max_bytes ? desc.max_bytes : uint64_t(1) << 30;
  // The capture at `ss` texels each way: a depth of 24 or 32 bits (4 bytes a texel) and, past
  // 1, its own three layers of 4 bytes (at 1 it draws into the atlas).
  const auto captureBytes = [&](uint64_t ss) {
    return width * ss * height * ss * (ss > 1 ? 16 : 4);
  };
  // The first of `sides` the capture at `ss` passes (null: none).
  const auto sidePassed = [&](uint64_t ss) -> const ImpostorSide* {
    for (const ImpostorSide& side : sides)
      if (width * ss > std::max<uint32_t>(side.limit, 1) ||
          height * ss > std::max<uint32_t>(side.limit, 1))
        return &side;
    return nullptr;
  };
  const auto fits = [&](uint64_t ss) {
    return sidePassed(ss) == nullptr && info.bytes + captureBytes(ss) <= budget;
  };
  info.capture_supersample = asked ? asked : (max_supersample >= 2 && fits(2) ? 2u : 1u);
  info.capture_bytes = captureBytes(info.capture_supersample);

  // The cell: every clip's bounds about their centre, as wide and tall as the widest view shows
  // them.
  Aabb box = palette.clips.empty() ? Aabb{} : palette.clips[0].bounds;
  for (const BakedClip& clip : palette.clips) {
    box.min = glm::min(box.min, clip.bounds.min);
    box.max = glm::max(box.max, clip.bounds.max);
  }
  plan.centre = 0.5f * (box.min + box.max);
  const glm::vec3 half = 0.5f * (box.max - box.min);
  float reach = 1e-6f;
  for (const glm::quat& q : viewRotations(plan))
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner =
          q * (half * glm::vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1));
      reach = std::max({reach, std::abs(corner.x), std::abs(corner.y)});
    }
  plan.cell_units = 2.0f * reach * 1.02f;
  *out = plan;

  // The atlas is an image, the capture's depth an attachment, drawn through one viewport: the
  // smallest of their limits bounds each side (a viewport past its limit would be clamped
  // silently, leaving cells empty).
  const uint64_t ss = info.capture_supersample;
  if (const ImpostorSide* side = sidePassed(ss))
    return {StatusCode::kLimitExceeded,
            strCat(call, ": ", plan.cells, " cells (", plan.frames.size(), " frames x ", views,
                   " views) of ", plan.cell, " texels need ", width, " x ", height,
                   " texels, captured ", ss, " x ", ss, " each: ", width * ss, " x ", height * ss,
                   ", past ", side->name, " (", side->limit,
                   "): fewer frames, views or texels per cell, or a smaller "
                   "capture_supersample")};
  // One capture instance per cell.
  if (plan.cells > HandlePool::kMaxSlots)
    return {StatusCode::kLimitExceeded,
            strCat(call, ": ", plan.cells, " cells (", plan.frames.size(), " frames x ", views,
                   " views), past the capture crowd's ", HandlePool::kMaxSlots,
                   " instances: fewer frames or views")};
  if (info.bytes + info.capture_bytes > budget)
    return {StatusCode::kLimitExceeded,
            strCat(call, ": the atlas takes ", info.bytes, " bytes with its mip levels and ",
                   "its capture ", info.capture_bytes, " more, past the budget of ", budget,
                   " (ImpostorDesc::max_bytes): fewer frames, views or texels per cell, a smaller "
                   "capture_supersample or a larger budget")};
  return Status::ok();
}

Status makeCaptureCrowd(const ImpostorPlan& plan, const BakedPalette& palette, uint32_t sub_meshes,
                        CrowdManager* crowd, Camera* camera) {
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = sub_meshes;
  cd.max_distance_radii = -1.0f;
  cd.worker_threads = 1;
  Status s = crowd->init(cd);
  const std::vector<glm::quat> rotations = viewRotations(plan);
  const uint32_t views = plan.info.views;
  const double cell_units = plan.cell_units;
  for (uint64_t i = 0; i < plan.cells && s.isOk(); ++i) {
    const CapturedFrame& f = plan.frames[i / views];
    const uint32_t view = uint32_t(i % views);
    const BakedClip& clip = palette.clips[f.clip];
    InstanceDesc inst;
    inst.clip = f.clip;
    inst.time_seconds = clip.frame_times_seconds.empty()
                            ? double(f.frame) * clip.frame_interval_seconds
                            : clip.frame_times_seconds[f.frame];
    inst.loop_mode = LoopMode::kOnce;  // The last frame held, not wrapped to the first.
    inst.speed = 0.0f;
    inst.rotation = rotations[view];
    inst.variation_mask = plan.mask;
    // Texture row i / columns from the bottom (row 0 at y = -rows cells).
    const glm::dvec3 cell_centre((double(i % plan.columns) + 0.5) * cell_units,
                                 (double(i / plan.columns) + 0.5 - double(plan.rows)) * cell_units,
                                 0.0);
    inst.position = cell_centre - glm::dvec3(inst.rotation * plan.centre);
    InstanceHandle handle;
    s = crowd->add(inst, &handle);
  }
  *camera = Camera();
  camera->position = glm::dvec3(0.0, 0.0, 2.0 * cell_units);
  camera->projection =
      glm::ortho(0.0f, float(plan.columns * cell_units), -float(plan.rows * cell_units), 0.0f, 0.0f,
                 float(4.0 * cell_units));
  camera->viewport_height_pixels = float(plan.info.height);
  if (s.isOk()) s = crowd->update(0.0, *camera);
  return s;
}

glm::vec4 impostorViewer(const Camera& camera) {
  const glm::mat4& v = camera.view_rotation;
  const bool ortho = camera.projection[3][3] == 1.0f && camera.projection[2][3] == 0.0f;
  return {v[0][2], v[1][2], v[2][2], ortho ? 1.0f : 0.0f};
}

ImpostorGrid impostorGrid(const ImpostorPlan& plan, const BakedPalette& palette) {
  ImpostorGrid g;
  g.clip_count = uint32_t(plan.clips.size());
  g.columns = plan.columns;
  g.rows = plan.rows;
  g.azimuths = plan.azimuths;
  g.elevations = uint32_t(plan.elevations_degrees.size());
  std::copy(std::begin(plan.elevations_radians), std::end(plan.elevations_radians),
            std::begin(g.elevations_radians));
  g.frame_stride_texels = palette.layout.frame_stride_texels;
  g.centre = plan.centre;
  g.cell_units = plan.cell_units;
  g.cell_texels = plan.cell;
  g.levels = plan.levels;
  return g;
}

std::vector<uint32_t> impostorClipTable(const ImpostorPlan& plan,
                                        const std::vector<uint32_t>& rects) {
  const size_t clip_words = plan.clips.size() * 4;
  std::vector<uint32_t> table(clip_words + (rects.size() + 3) / 4 * 4, 0u);
  for (size_t k = 0; k < plan.clips.size(); ++k)
    for (int c = 0; c < 4; ++c) table[k * 4 + size_t(c)] = plan.clips[k][c];
  std::copy(rects.begin(), rects.end(), table.begin() + ptrdiff_t(clip_words));
  return table;
}

}  // namespace si::detail
