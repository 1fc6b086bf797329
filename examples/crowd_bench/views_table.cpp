// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/views_table.h"
#include "crowd_bench/bench_character.h"
#include "crowd_bench/gpu_passes_table.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "common/cascades.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/crowd_view.h"

namespace si::bench {

namespace {

// Times `path` on the field of `count` with 1 main view and views - 1 cascades.
Status runViews(Setup& setup, Renderer& renderer, const BakedPalette& palette, uint32_t count,
                const std::string& path, uint32_t views, uint32_t lod_bias, const LodChoice& lod,
                Row* row) {
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  CrowdManager crowd;
  Status s = makeCrowd(setup, palette, places, lod, &crowd);
  CrowdView main_view;
  std::vector<std::unique_ptr<CrowdView>> cascades;
  if (s.isOk()) s = main_view.init(crowd);
  CrowdViewDesc shadow;
  shadow.lod_bias = lod_bias;
  shadow.max_distance_radii = -1.0f;
  for (uint32_t k = 1; k < views && s.isOk(); ++k) {
    cascades.push_back(std::make_unique<CrowdView>());
    s = cascades.back()->init(crowd, shadow);
  }
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  if (!s.isOk()) return s;
  const glm::vec3 sun(-0.4f, -1.0f, -0.3f);
  std::vector<Camera> lights;
  // The crowd's bounding sphere on the ground: the cascades cover the part of the main
  // camera's depth range where characters stand.
  glm::dvec3 centre(0.0);
  for (const glm::dvec3& p : places) centre += p / double(std::max<size_t>(1, places.size()));
  double scene_radius = 2.0;
  for (const glm::dvec3& p : places) scene_radius = std::max(scene_radius, glm::length(p - centre) + 2.0);
  // The cascades fit the height range the characters stand in (their positions, up to two
  // bounding radii above).
  const double radius = double(si::CrowdExport::cullParams(crowd.view(), Camera()).radius);
  double low = 1e30, high = -1e30;
  for (const glm::dvec3& p : places) low = std::min(low, p.y), high = std::max(high, p.y);
  row->scene = "field";
  row->path = path;
  row->lod = std::to_string(views) + (views == 1 ? " view" : " views");
  row->pass_bytes = false;  // Several draws a frame: no byte estimate.
  row->instances = count;
  const bool gpu = isGpuSelected(path);
  const bool occlusion = gpu && path.size() > 10 && path.compare(path.size() - 10, 10, "-occlusion") == 0;
  renderer.setGpuOcclusionCulling(occlusion);
  PassCollector passes(renderer);  // --gpu-passes: each frame's views summed.
  uint32_t frame = 0;
  const Status timed = timeFrames(
      setup, "field", places,
      [&](const Camera& cam) {
        // The crowd's simulation once, then each view's selection (on the GPU-driven paths the
        // clock only: the draws select).
        Status st = gpu ? crowd.advance(1.0 / 60.0) : crowd.advance(1.0 / 60.0);
        if (st.isOk() && !gpu) st = main_view.select(cam);
        const glm::mat4& v = cam.view_rotation;
        const glm::dvec3 forward = -glm::dvec3(v[0][2], v[1][2], v[2][2]);
        const double depth = glm::dot(centre - cam.position, forward);
        lights = si::examples::cascadeCameras(cam, uint32_t(cascades.size()), sun, float(setup.height),
                                              std::max(1.0, depth - scene_radius), depth + scene_radius,
                                              low - radius, high + 2.0 * radius);
        for (size_t k = 0; k < cascades.size() && st.isOk() && !gpu; ++k)
          st = cascades[k]->select(lights[k]);
        return st;
      },
      [&](const Camera& cam, DrawStats* st, uint32_t* visible) {
        // Each cascade depth-only (into the bench's framebuffer, cleared between them as a
        // shadow map would be), then the main view in colour; the statistics summed.
        const auto draw_view = [&](const CrowdView& view, const Camera& at, DrawMode mode) {
          renderer.clear(kClearColor);
          DrawStats one;
          const Status drawn =
              gpu ? renderer.drawCrowdGpuCulled(CharacterId{}, view, at, &one, mode)
              : path == "traditional" ? renderer.drawTraditional(CharacterId{}, view, at, &one)
              : path == "cpu"
                  ? renderer.drawCpuSkinned(CharacterId{}, view, at, &one)
                  : renderer.drawCrowd(si::CharacterId{}, view, batcher, at, &one, mode);
          st->gpu_visible += one.gpu_visible;
          st->cpu_submit_ms += one.cpu_submit_ms;
          // No GPU time (--no-gpu-time) reads -1 for the frame, not a sum of them.
          st->gpu_ms = one.gpu_ms >= 0.0 && st->gpu_ms >= 0.0 ? st->gpu_ms + one.gpu_ms : -1.0;
          st->draw_calls += one.draw_calls;
          st->triangles += one.triangles;
          if (frame >= kWarmupFrames) passes.add(one.gpu_pass_ticket, frame);
          return drawn;
        };
        Status drawn = Status::ok();
        st->gpu_ms = 0.0;  // The views' sum (-1 when a view has none).
        for (size_t k = 0; k < cascades.size() && drawn.isOk(); ++k)
          drawn = draw_view(*cascades[k], lights[k], DrawMode::kDepthOnly);
        const DrawMode mode = path == "compute" ? DrawMode::kComputeSkinned
                              : path == "rigid" ? DrawMode::kRigid
                                                : DrawMode::kDefault;
        if (drawn.isOk()) drawn = draw_view(main_view, cam, mode);
        ++frame;
        if (gpu) {
          *visible = st->gpu_visible;
        } else {
          *visible = main_view.stats().visible;
          for (const auto& c : cascades) *visible += c->stats().visible;
        }
        return drawn;
      },
      row);
  renderer.setGpuOcclusionCulling(false);
  passes.finish(row);
  return timed;
}

}  // namespace

Status viewsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                  const std::vector<uint32_t>& sizes, const std::vector<uint32_t>& view_counts,
                  uint32_t cascade_lod_bias, const LodChoice& lod,
                  const std::vector<std::string>& paths, uint32_t max_baseline, std::FILE* csv,
                  const std::string& passes_csv) {
  // The instanced paths and the baselines name their mode; the GPU-driven paths draw kDefault
  // and kDepthOnly on the renderer's skinning path: the vertex shader for gpu-culled*, compute
  // pre-skinning for gpu-driven*.
  Renderer renderers[2];
  for (int k = 0; k < 2; ++k) {
    RendererDesc rd = desc;
    rd.skinning_path = k == 0 ? SkinningPath::kVertexShader : SkinningPath::kCompute;
    // A region of the record ring per draw of 3 frames, so no view waits for another's.
    rd.ring_frames = 3 * *std::max_element(view_counts.begin(), view_counts.end());
    const Status s = initRenderer(setup, palette, rd, &renderers[k]);
    if (!s.isOk()) return {s.code(), "views: " + s.message()};
  }
  Status s = Status::ok();
  std::printf(
      "\nViews (field, %s LODs): 1 main view and N - 1 shadow cascades per frame "
      "(CrowdManager::advance once, CrowdView::select per view, or the clock and a GPU "
      "selection per view on the GPU-driven paths; cascades depth-only, %u LOD%s "
      "coarser), side by side with the main view alone; visible sums the views\n",
      lod.name().c_str(), cascade_lod_bias, cascade_lod_bias == 1 ? "" : "s");
  printSideBySideHeader("views");
  std::printf("\n");
  std::vector<Row> all;  // For the pass table (--gpu-passes).
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      Renderer& renderer = renderers[path.compare(0, 10, "gpu-driven") == 0 ? 1 : 0];
      if ((path == "traditional" || path == "cpu") && count > max_baseline) continue;
      std::vector<Row> rows(view_counts.size());
      for (size_t k = 0; k < view_counts.size(); ++k) {
        s = runViews(setup, renderer, palette, count, path, view_counts[k], cascade_lod_bias, lod,
                     &rows[k]);
        if (!s.isOk()) return {s.code(), "views, " + path + ": " + s.message()};
      }
      for (const Row& r : rows) {
        printSideBySideRow(r, rows[0], "views", csv);
        std::printf("\n");
      }
      all.insert(all.end(), rows.begin(), rows.end());
    }
  if (desc.measure_gpu_passes) printPassTable(all, passes_csv.c_str());
  for (Renderer& r : renderers) r.shutdown();
  return Status::ok();
}

}  // namespace si::bench
