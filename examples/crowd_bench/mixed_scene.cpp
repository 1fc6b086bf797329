// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/mixed_scene.h"

#include <algorithm>
#include <filesystem>
#include <memory>

#include "common/character_kinds.h"

namespace si::bench {

Status loadMixedKinds(const Character& main, const BakedPalette& main_palette,
                      const std::vector<std::string>& files, bool lod_chain, bool quick,
                      std::vector<MixedKind>* out) {
  out->clear();
  out->push_back({"embedded", main, main_palette});
  BakeDesc bake;
  if (quick) bake.rate_mode = RateMode::kFixed;
  for (const std::string& file : files) {
    MixedKind k;
    Status s = examples::importAndBake(file, bake, lod_chain, &k.character, &k.palette, nullptr);
    if (!s.isOk()) return s;
    k.name = std::filesystem::path(file).stem().string();
    std::printf("Mixed kind %s: %zu vertices, %zu LOD levels (LOD 0: %zu triangles, last: %zu)\n",
                k.name.c_str(), k.character.mesh.vertexCount(), k.character.mesh.maxLodCount(),
                k.character.mesh.triangleCount(0, 0),
                k.character.mesh.triangleCount(0, k.character.mesh.maxLodCount() - 1));
    out->push_back(std::move(k));
  }
  return Status::ok();
}

Status runMixed(Setup& setup, const std::vector<MixedKind>& kinds, const RendererDesc& desc,
                uint32_t count, const std::string& path, bool one_renderer, MixedRow* row) {
  const size_t n_kinds = kinds.size();
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  std::vector<std::unique_ptr<Renderer>> renderers;
  std::vector<CharacterId> ids(n_kinds);
  std::vector<std::unique_ptr<CrowdManager>> crowds;
  Status s;
  const float height = std::max(setup.character.height(), 1e-6f);
  for (size_t k = 0; k < n_kinds && s.isOk(); ++k) {
    const MixedKind& kind = kinds[k];
    if (renderers.empty() || !one_renderer) {
      renderers.push_back(std::make_unique<Renderer>());
      s = renderers.back()->init(setup.info, desc);
    }
    if (s.isOk()) s = renderers.back()->addCharacter(kind.character, kind.palette, &ids[k]);
    CrowdDesc cd;
    cd.max_distance_radii = -1.0f;  // As the paths table: everything in view, however far.
    // Kind k takes places k, k + n_kinds, ...; its largest extent is the embedded height.
    std::vector<glm::dvec3> at;
    for (size_t i = k; i < places.size(); i += n_kinds) at.push_back(places[i]);
    RandomCrowdDesc rc;
    rc.seed = 2026 + k;
    const uint32_t parts = uint32_t(kind.character.mesh.sub_meshes.size());
    rc.required_mask = k == 0 ? 1u : 0xFFFFFFFFu >> (32 - std::min<uint32_t>(parts, 32));
    rc.optional_mask = k == 0 ? 0xEu : 0u;
    crowds.push_back(std::make_unique<CrowdManager>());
    if (s.isOk())
      s = examples::makeScaledCrowd(kind.character, kind.palette, cd, at, height, rc,
                                    crowds.back().get());
  }
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderers.front()->batchLimits());
  if (!s.isOk()) return s;
  row->path = path;
  row->one_renderer = one_renderer;
  row->instances = count;
  s = timeFrames(
      setup, "field", places,
      [&](const Camera& cam) {
        Status stepped;
        for (auto& c : crowds)
          if (stepped.isOk()) stepped = stepCrowd(*c, path, cam, 1.0 / 60.0);
        return stepped;
      },
      [&](const Camera& cam, DrawStats* sum, uint32_t* visible) {
        renderers.front()->clear(kClearColor);
        sum->gpu_ms = 0.0;
        Status drawn;
        for (size_t k = 0; k < n_kinds && drawn.isOk(); ++k) {
          Renderer& r = *renderers[one_renderer ? 0 : k];
          DrawStats st;
          drawn = drawKind(r, ids[k], *crowds[k], batcher, path, cam, &st);
          examples::accumulate(st, sum);
          *visible += isGpuSelected(path) ? st.gpu_visible : crowds[k]->view().stats().visible;
        }
        return drawn;
      },
      row);
  for (auto& r : renderers) r->shutdown();
  return s;
}

Status mixedTable(Setup& setup, const std::vector<MixedKind>& kinds, const RendererDesc& desc,
                  const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                  uint32_t max_baseline, std::FILE* csv) {
  std::string names;
  for (const MixedKind& k : kinds) names += (names.empty() ? "" : ", ") + k.name;
  std::printf("\nMixed scene (field; %zu kinds sharing it round-robin: %s): one renderer for every "
              "kind against one renderer per kind, in the same run\n",
              kinds.size(), names.c_str());
  std::printf("%-11s %-9s %9s %9s %6s %12s %9s %9s %9s %8s %8s\n", "path", "renderers",
              "instances", "visible", "draws", "triangles", "update", "submit", "GPU ms",
              "CPU x", "GPU x");
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      if ((path == "traditional" || path == "cpu") && count > max_baseline) continue;
      MixedRow rows[2];
      for (int one = 1; one >= 0; --one) {
        Status s = runMixed(setup, kinds, desc, count, path, one == 1, &rows[1 - one]);
        if (!s.isOk()) return {s.code(), "mixed scene, " + path + ": " + s.message()};
      }
      const MixedRow& separate = rows[1];
      for (const MixedRow& r : rows) {
        const double cpu = r.update_ms + r.submit_ms;
        const double cpu_x = cpu / std::max(1e-9, separate.update_ms + separate.submit_ms);
        const double gpu_x = r.gpu_ms / std::max(1e-9, separate.gpu_ms);
        std::printf("%-11s %-9s %9u %9u %6u %12.0f %9.3f %9.3f %9.3f %8.2f %8.2f\n",
                    r.path.c_str(), r.one_renderer ? "one" : "per kind", r.instances, r.visible,
                    r.draws, r.triangles, r.update_ms, r.submit_ms, r.gpu_ms, cpu_x, gpu_x);
        std::fprintf(csv, "mixed,field,%s,%u,%u,%u,%.0f,%.4f,%.4f,%.4f,,,,,%s,,,\n",
                     r.path.c_str(), r.instances, r.visible, r.draws, r.triangles, r.update_ms,
                     r.submit_ms, r.gpu_ms, r.one_renderer ? "one-renderer" : "per-kind");
      }
    }
  return Status::ok();
}

}  // namespace si::bench
