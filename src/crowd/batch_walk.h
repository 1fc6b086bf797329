// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// How InstanceBatcher cuts a view's buckets into batches, shared by its build functions and by
// what the back-ends lay out in the same slots (composed_places.h). No GL.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "si/crowd/crowd_view.h"
#include "si/crowd/instance_batcher.h"

namespace si::detail {

inline size_t alignUp(size_t v, size_t a) { return (v + a - 1) / a * a; }

// build()'s walk: every bucket cut into batches of at most `capacity` entries at aligned
// offsets (records at byte_offset, layer records at layer_byte_offset), each filled from
// consecutive pieces of the bucket's runs by copy(batch, slot, first, count): records()[first ..
// first + count) go to the batch's slots from `slot` on. Adds each batch to `draws` when
// non-null.
template <typename CopyRun>
void walkBatches(const CrowdView& crowd, uint32_t capacity, uint32_t alignment,
                 std::vector<DrawBatch>* draws, const CopyRun& copy) {
  const std::vector<uint32_t>& offsets = crowd.bucketOffsets();
  const std::vector<uint32_t>& run_offsets = crowd.bucketRunOffsets();
  const std::vector<RecordRun>& runs = crowd.bucketRuns();
  const uint32_t submeshes = crowd.subMeshCount();
  size_t cursor = 0, layer_cursor = 0;
  for (uint32_t b = 0; b + 1 < offsets.size(); ++b) {
    uint32_t r = run_offsets[b], used_of_run = 0;
    for (uint32_t left = offsets[b + 1] - offsets[b]; left > 0;) {
      const uint32_t n = std::min(capacity, left);
      cursor = alignUp(cursor, alignment);
      layer_cursor = alignUp(layer_cursor, alignment);
      DrawBatch d;
      d.lod = static_cast<uint16_t>(b / submeshes);
      d.sub_mesh = static_cast<uint16_t>(b % submeshes);
      d.byte_offset = static_cast<uint32_t>(cursor);
      d.instance_count = n;
      d.layer_byte_offset = static_cast<uint32_t>(layer_cursor);
      for (uint32_t copied = 0; copied < n;) {
        const RecordRun& run = runs[r];
        const uint32_t take = std::min(n - copied, run.count - used_of_run);
        copy(d, copied, run.first + used_of_run, take);
        copied += take;
        used_of_run += take;
        if (used_of_run == run.count) {
          ++r;
          used_of_run = 0;
        }
      }
      cursor += size_t(n) * kInstanceRecordSize;
      layer_cursor += size_t(n) * kLayerRecordSize;
      if (draws != nullptr) draws->push_back(d);
      left -= n;
    }
  }
}

}  // namespace si::detail
