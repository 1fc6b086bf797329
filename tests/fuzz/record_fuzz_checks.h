// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd API fuzzer's checks of an update's instance records (crowd_api_fuzz.cpp): world
// rows, frames (the palette's or a live pose's), fractions and weights, and the morph weights
// they draw.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "si/core/baked_palette.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/record_emulation.h"

namespace si::fuzz {

// Every record of the crowd's own view: finite world rows; frames inside the palette, or one
// live pose's frame after it; fractions and the crossfade weight in [0, 1]; the morph weights
// it draws, overlays mixed in, within the clips' (every key in [0, 1]).
inline void checkRecords(const CrowdManager& crowd, const BakedPalette& palette,
                         void (*fail)(const char*)) {
  const uint64_t texels = palette.layout.textureTexelCount();
  // The drawn morph weights, overlays mixed in, stay within the clips' (every key in [0, 1]).
  const Span<const LayerRecord> layers = crowd.view().layerRecords();
  std::vector<float> weights(palette.layout.morph_target_count);
  for (size_t i = 0; i < crowd.view().records().size(); ++i) {
    const InstanceRecord& r = crowd.view().records()[i];
    if (r.frames[0] >= texels) continue;  // A live pose: its weights are a baked frame's.
    const Span<const LayerRecord> extras =
        crowd.view().extraLayerRecords().empty()
            ? Span<const LayerRecord>()
            : Span<const LayerRecord>(
                  crowd.view().extraLayerRecords().data() + i * kExtraLayerRecords,
                  kExtraLayerRecords);
    const Status w = layers.empty() ? emulateRecordMorphWeights(palette, r, weights)
                                    : emulateLayeredMorphWeights(palette, r, layers[i], extras,
                                                                 crowd.layerMasks(), weights);
    if (!w.isOk()) fail("the morph weights of a drawn record cannot be emulated");
    for (float v : weights)
      if (!(v >= -1e-6f && v <= 1.0f + 1e-6f)) fail("a drawn morph weight is outside its clips'");
  }
  for (const InstanceRecord& r : crowd.view().records()) {
    for (const auto& row : r.world_rows)
      for (float v : row)
        if (!std::isfinite(v)) fail("a record's world rows are not finite");
    // Inside the palette, or a live pose's frame after it (the four frames that one).
    const uint32_t stride = palette.layout.frame_stride_texels;
    const uint64_t live_end = texels + uint64_t(crowd.desc().live_pose_capacity) * stride;
    for (uint32_t f : r.frames)
      if (uint64_t(f) + stride > live_end ||
          (f >= texels && ((f - texels) % stride != 0 || f != r.frames[0])))
        fail("a frame is outside the palette and its live poses");
    for (int k = 0; k < 3; ++k) {
      IntervalMode mode;
      float v = unpackFraction(r.blend[k], &mode);
      if (k == 2) std::memcpy(&v, &r.blend[k], 4);  // The weight carries no mode.
      if (!(v >= 0.0f && v <= 1.0f)) fail("a record's fraction or weight is outside [0, 1]");
    }
  }
}

}  // namespace si::fuzz
