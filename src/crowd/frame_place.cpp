// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The frame builder's place phase (frame_builder.h): the chunks' worn masks merged into the
// frame's groups, every (LOD, group) key's range of records by prefix sums, and each chunk's
// cursor per key, so the write phase puts every record at its sorted place.
#include <algorithm>

#include "crowd/frame_builder.h"

namespace si::detail {

void placeChunks(const FrameInputs& in, uint32_t chunk_count, CrowdFrame& f, bool* fallback) {
  const uint32_t lods = in.params.lod_count;
  f.group_masks.clear();
  bool overflow = false;
  for (uint32_t c = 0; c < chunk_count; ++c) {
    const ChunkWork& w = f.chunks[c];
    overflow |= w.mask_overflow;
    f.group_masks.insert(f.group_masks.end(), w.masks, w.masks + w.mask_count);
    CrowdFrameStats& s = f.stats;
    s.culled_frustum += w.stats.culled_frustum;
    s.culled_distance += w.stats.culled_distance;
    for (uint32_t l = 0; l < 8; ++l) s.per_lod[l] += w.stats.per_lod[l];
    s.visible += w.visible_count;
  }
  std::sort(f.group_masks.begin(), f.group_masks.end());
  f.group_masks.erase(std::unique(f.group_masks.begin(), f.group_masks.end()), f.group_masks.end());
  *fallback = overflow || f.group_masks.size() > kMaxMaskGroups;
  if (*fallback || f.group_masks.empty()) f.group_masks.assign(1, 0u);
  const uint32_t groups = uint32_t(f.group_masks.size());
  // Totals per key (LOD-major, groups by increasing mask), then prefix sums.
  f.key_offsets.assign(size_t(lods) * groups + 1, 0u);
  for (uint32_t c = 0; c < chunk_count; ++c) {
    ChunkWork& w = f.chunks[c];
    for (uint32_t g = 0; g < w.mask_count; ++g)
      w.to_group[g] =
          *fallback
              ? 0u
              : uint32_t(std::lower_bound(f.group_masks.begin(), f.group_masks.end(), w.masks[g]) -
                         f.group_masks.begin());
    for (uint32_t l = 0; l < lods; ++l)
      for (uint32_t g = 0; g < w.mask_count; ++g)
        f.key_offsets[l * groups + w.to_group[g] + 1] += w.counts[l * kMaxMaskGroups + g];
  }
  for (size_t k = 1; k < f.key_offsets.size(); ++k) f.key_offsets[k] += f.key_offsets[k - 1];
  // Cursors: within a key, chunks in order. In the fallback, a chunk's groups of one LOD share
  // one cursor (kept in the group-0 slot), so its records stay in dense order.
  std::vector<uint32_t>& running = f.bucket_cursor_scratch;
  running.assign(f.key_offsets.begin(), f.key_offsets.end() - 1);
  for (uint32_t c = 0; c < chunk_count; ++c) {
    ChunkWork& w = f.chunks[c];
    for (uint32_t l = 0; l < lods; ++l) {
      if (*fallback) {
        uint32_t n = 0;
        for (uint32_t g = 0; g < w.mask_count; ++g) n += w.counts[l * kMaxMaskGroups + g];
        w.cursor[l * kMaxMaskGroups] = running[l];
        running[l] += n;
        continue;
      }
      for (uint32_t g = 0; g < w.mask_count; ++g) {
        const uint32_t key = l * groups + w.to_group[g];
        w.cursor[l * kMaxMaskGroups + g] = running[key];
        running[key] += w.counts[l * kMaxMaskGroups + g];
      }
    }
  }
}

}  // namespace si::detail
