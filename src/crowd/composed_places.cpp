// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The composed records' places (composed_places.h).
#include "crowd/composed_places.h"

#include <algorithm>

#include "crowd/batch_walk.h"

namespace si::detail {

uint32_t writeComposedPlaces(const InstanceBatcher& batcher, const CrowdView& view,
                             Span<const uint8_t> drawn_buckets, Span<uint32_t> entries,
                             Span<uint32_t> slot_records) {
  std::fill(entries.begin(), entries.end(), kNotComposed);
  const uint32_t sub_meshes = view.subMeshCount();
  uint32_t drawn = 0;
  walkBatches(view, batcher.capacityPerDraw(), batcher.alignment(), nullptr,
              [&](const DrawBatch& d, uint32_t slot, uint32_t first, uint32_t count) {
                const size_t bucket = size_t(d.lod) * sub_meshes + d.sub_mesh;
                if (bucket >= drawn_buckets.size() || drawn_buckets[bucket] == 0) return;
                const uint32_t word = (d.byte_offset + slot * kInstanceRecordSize) / 16;
                const uint32_t first_slot = d.layer_byte_offset / kLayerRecordSize + slot;
                for (uint32_t k = 0; k < count; ++k) {
                  slot_records[first_slot + k] = first + k;
                  uint32_t* entry = &entries[size_t(first + k) * 2];
                  if (entry[0] != kNotComposed) continue;
                  entry[0] = word + k * (kInstanceRecordSize / 16);
                  entry[1] = first_slot + k;
                  ++drawn;
                }
              });
  return drawn;
}

}  // namespace si::detail
