// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/crowds_table.h"
#include "crowd_bench/bench_character.h"

#include <memory>

namespace si::bench {

namespace {

constexpr double kMiB = 1024.0 * 1024.0;

// `count` crowds of `size`: the field of count x size places, cut into count slices.
Status runCrowds(Setup& setup, Renderer& renderer, const BakedPalette& palette, uint32_t size,
                 uint32_t count, Row* row, GpuMemory* memory) {
  const std::vector<glm::dvec3> places = scenePositions("field", size * count);
  std::vector<std::unique_ptr<CrowdManager>> crowds;
  Status s = Status::ok();
  for (uint32_t k = 0; k < count && s.isOk(); ++k) {
    crowds.push_back(std::make_unique<CrowdManager>());
    const std::vector<glm::dvec3> slice(places.begin() + size_t(k) * size,
                                        places.begin() + size_t(k + 1) * size);
    s = makeCrowd(setup, palette, slice, LodChoice(), crowds.back().get());
  }
  if (!s.isOk()) return s;
  row->path = "gpu-driven";
  row->lod = std::to_string(count) + (count == 1 ? " crowd" : " crowds");
  row->instances = size * count;
  s = timeFrames(
      setup, "field", places,
      [&](const Camera&) {
        Status st = Status::ok();
        for (auto& c : crowds)
          if (st.isOk()) st = c->advance(1.0 / 60.0);
        return st;
      },
      [&](const Camera& cam, DrawStats* st, uint32_t* visible) {
        renderer.clear(kClearColor);
        Status drawn = Status::ok();
        st->gpu_ms = 0.0;
        *visible = 0;
        for (auto& c : crowds) {
          DrawStats one;
          if (drawn.isOk())
            drawn = renderer.drawCrowdGpuCulled(si::CharacterId{}, c->view(), cam, &one);
          st->cpu_submit_ms += one.cpu_submit_ms;
          st->gpu_ms = one.gpu_ms >= 0.0 && st->gpu_ms >= 0.0 ? st->gpu_ms + one.gpu_ms : -1.0;
          st->draw_calls += one.draw_calls;
          st->triangles += one.triangles;
          *visible += one.gpu_visible;
        }
        return drawn;
      },
      row);
  if (s.isOk()) s = renderer.gpuMemory(memory);
  return s;
}

}  // namespace

Status crowdsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                   const std::vector<uint32_t>& sizes, const std::vector<uint32_t>& crowd_counts,
                   std::FILE* csv) {
  std::printf(
      "\nSeveral crowds of one character (field, gpu-driven, pre-skinned): N crowds of "
      "each size side by side, each stepped and drawn every frame; medians of the "
      "frame's N draws; GPU memory after the last frame\n");
  std::printf("%9s %7s %10s %9s %10s %10s %12s %11s %10s\n", "instances", "crowds", "total",
              "visible", "submit ms", "GPU ms", "MiB/crowd", "MiB staging", "MiB all");
  for (uint32_t size : sizes)
    for (uint32_t count : crowd_counts) {
      // A renderer per row: its memory is the row's alone.
      Renderer renderer;
      RendererDesc rd = desc;
      rd.skinning_path = SkinningPath::kCompute;
      Status s = initRenderer(setup, palette, rd, &renderer);
      Row row;
      GpuMemory memory;
      if (s.isOk()) s = runCrowds(setup, renderer, palette, size, count, &row, &memory);
      renderer.shutdown();
      if (!s.isOk()) return {s.code(), "crowds: " + s.message()};
      double per_crowd = 0.0;
      for (const CharacterGpuMemory& c : memory.characters)
        for (const CrowdGpuMemory& k : c.crowds) per_crowd += double(k.state_bytes + k.view_bytes);
      per_crowd /= std::max(1u, count);
      std::printf("%9u %7u %10u %9u %10.3f %10.3f %12.1f %11.1f %10.1f\n", size, count,
                  row.instances, row.visible, row.submit_ms, row.gpu_ms, per_crowd / kMiB,
                  double(memory.staging_bytes) / kMiB, double(memory.total()) / kMiB);
      std::fprintf(csv, "crowds,field,gpu-driven,%u,%u,%u,%.0f,%.4f,%.4f,%.4f,,%.1f,,%s,,,\n",
                   row.instances, row.visible, row.draws, row.triangles, row.update_ms,
                   row.submit_ms, row.gpu_ms, double(memory.total()) / kMiB, row.lod.c_str());
    }
  return Status::ok();
}

}  // namespace si::bench
