// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd API fuzzer's checks of an update's layer records (crowd_api_fuzz.cpp): overlays'
// and 2D blends' extra layers, and the batcher's layouts of both.

#include <cstdint>
#include <vector>

#include "si/core/baked_palette.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

namespace si::fuzz {

// Layered animation: none, or one layer record per record, naming an added mask where its
// weight is not 0, with frames inside the palette; with a 2D space two extra layer records per
// record likewise, the layer record flagging them exactly when one has a weight; the batcher
// lays them all out.
inline void checkLayerRecords(const CrowdManager& crowd, const InstanceBatcher& batcher,
                              const BakedPalette& palette, void (*fail)(const char*)) {
  const uint64_t texels = palette.layout.textureTexelCount();
  const auto check = [&](const LayerRecord& l) {
    if (layerWeight(l) > 0.0f && layerMask(l) >= crowd.layerMasks().size())
      fail("a layer record names a mask the crowd does not hold");
    if (!(layerWeight(l) >= 0.0f && layerWeight(l) <= 1.0f))
      fail("a layer weight is outside [0, 1]");
    for (uint32_t f : l.frames)
      if (uint64_t(f) + palette.layout.frame_stride_texels > texels)
        fail("an overlay frame is outside the palette");
  };
  const auto layers = crowd.view().layerRecords();
  const auto extras = crowd.view().extraLayerRecords();
  if (layers.empty()) {
    if (!extras.empty()) fail("extra layer records without layer records");
    return;
  }
  if (layers.size() != crowd.view().records().size())
    fail("the layer records do not match the records");
  const bool grid = si::CrowdExport(crowd).writesExtraLayers();
  if (extras.size() != (grid ? layers.size() * kExtraLayerRecords : 0))
    fail("the extra layer records do not match the records");
  for (size_t i = 0; i < layers.size(); ++i) {
    check(layers[i]);
    bool drawn = false;
    for (uint32_t k = 0; k < kExtraLayerRecords && grid; ++k) {
      const LayerRecord& e = extras[i * kExtraLayerRecords + k];
      check(e);
      drawn = drawn || layerWeight(e) > 0.0f;
    }
    if (layerHasExtras(layers[i]) != drawn) fail("a layer record's extras flag is wrong");
  }
  std::vector<uint8_t> layer_bytes(batcher.layerBufferBound(crowd.view()));
  if (!batcher.buildLayers(crowd.view(), layer_bytes).isOk())
    fail("buildLayers failed on a valid frame");
  std::vector<uint8_t> extra_bytes(batcher.extraLayerBufferBound(crowd.view()));
  if (grid && !batcher.buildExtraLayers(crowd.view(), extra_bytes).isOk())
    fail("buildExtraLayers failed on a valid frame");
  if (crowd.desc().previous_records) {
    const auto previous = crowd.view().previousLayerRecords();
    if (!previous.empty() && previous.size() != crowd.view().previousRecords().size())
      fail("the previous layer records do not match the previous records");
    const auto previous_extras = crowd.view().previousExtraLayerRecords();
    if (!previous_extras.empty() &&
        previous_extras.size() != crowd.view().previousRecords().size() * kExtraLayerRecords)
      fail("the previous extra layer records do not match the previous records");
    if (!batcher.buildPreviousLayers(crowd.view(), layer_bytes).isOk())
      fail("buildPreviousLayers failed on a valid frame");
    if (grid && !batcher.buildPreviousExtraLayers(crowd.view(), extra_bytes).isOk())
      fail("buildPreviousExtraLayers failed on a valid frame");
  }
}

}  // namespace si::fuzz
