// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/layers_table.h"

#include <algorithm>

#include "si/bake/layer_error.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_manager.h"

namespace si::bench {

namespace {

// Off, full, half-way; full and half-way again with composing off (RendererDesc::compose_layers:
// each vertex walks its influences' chains).
constexpr float kWeights[] = {0.0f, 1.0f, 0.5f, 1.0f, 0.5f};
const char* const kNames[] = {"off", "w=1", "w=0.5", "walk1", "walk.5"};
constexpr int kComposedStates = 3;

// Times `path` on the field of `count`, every instance's overlay held at `weight` (0: none).
Status runLayers(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                 const LayerMask& arm, uint32_t wave, uint32_t count, const std::string& path,
                 int state, Row* row) {
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  CrowdManager crowd;
  LodChoice lod;
  std::vector<InstanceHandle> handles;
  Status s = makeCrowd(setup, palette, places, lod, &crowd, &handles);
  uint32_t mask = 0;
  if (s.isOk() && kWeights[state] > 0.0f) {
    s = crowd.addLayerMask(arm, &mask);
    for (size_t i = 0; s.isOk() && i < handles.size(); ++i)  // Out of step with each other.
      s = crowd.playOverlay(handles[i], wave, mask, kWeights[state], 0.0, 0.37 * double(i % 7));
  }
  if (!s.isOk()) return s;
  row->lod = kNames[state];
  return timeCrowd(setup, renderer, crowd, "field", places, path, row);
}

}  // namespace

Status layersTable(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                   const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                   std::FILE* csv) {
  const int32_t wave = palette.findClip("wave"), walk = palette.findClip("walk");
  if (wave < 0 || walk < 0)
    return {StatusCode::kNotFound, "layers: the palette has no 'wave' or 'walk' clip"};
  LayerMask arm;
  Status s = buildLayerMask(setup.character.skeleton, palette, "right arm", {"r_clavicle"}, &arm);
  if (!s.isOk()) return s;
  LayeredErrorReport error;
  s = measureLayeredError(setup.character, palette, arm, uint32_t(walk), uint32_t(wave),
                          {0.5f, 1.0f}, &error, 32);
  if (!s.isOk()) return s;
  std::printf(
      "\nLayered animation (field; every instance waves its right arm over its clip): "
      "no overlay against weight 1 and weight 0.5, in the same run (composed layers; "
      "walk1, walk.5: weight 1 and 0.5 with composing off, each vertex walking its "
      "chains)\n");
  const size_t masked = size_t(std::count_if(arm.slot_anchor.begin(), arm.slot_anchor.end(),
                                             [](int32_t a) { return a != LayerMask::kNotInMask; }));
  std::printf(
      "The right arm's mask: %zu of %zu palette slots (composed rows: %zu bytes per "
      "drawn instance)\n",
      masked, arm.slot_anchor.size(), masked * 48);
  printSideBySideHeader("layer");
  std::printf("\n");
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      if (path != "instanced" && path != "compute" && path != "gpu-culled" && path != "gpu-driven")
        continue;
      Row rows[5];
      for (int state = 0; state < 5; ++state) {
        renderer.setComposeLayers(state < kComposedStates);
        s = runLayers(setup, renderer, palette, arm, uint32_t(wave), count, path, state, &rows[state]);
        renderer.setComposeLayers(true);
        if (!s.isOk()) return {s.code(), "layers, " + path + ": " + s.message()};
        printSideBySideRow(rows[state], rows[0], "layers", csv);
        std::printf("\n");
      }
    }
  std::printf("Layered error against the local-space reference (walk + wave, %u samples): "
              "weight 0.5 %.3g units (%.2g of the height), weight 1 %.3g units (%.2g)\n",
              error.samples, error.per_weight[0].max_error_units, error.per_weight[0].max_error_ratio,
              error.per_weight[1].max_error_units, error.per_weight[1].max_error_ratio);
  return Status::ok();
}

}  // namespace si::bench
