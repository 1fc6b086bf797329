// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A frame's buckets as runs of consecutive records. The records lie sorted by (LOD, worn mask),
// so bucket (l, s) is the LOD's groups whose mask wears s: consecutive groups that all wear it
// join into one run (the body, worn by all, is one run per LOD).
#include <algorithm>

#include "crowd/frame_builder.h"

namespace si::detail {

namespace {

// Appends [first, first + count) to the current bucket's runs, joining it to the last run when
// they touch.
void appendRun(CrowdFrame& f, uint32_t bucket_first_run, uint32_t first, uint32_t count) {
  if (count == 0) return;
  if (f.runs.size() > bucket_first_run && f.runs.back().first + f.runs.back().count == first) {
    f.runs.back().count += count;
    return;
  }
  f.runs.push_back({first, count});
}

}  // namespace

void buildBucketRuns(uint32_t lods, uint32_t sub_meshes, bool fallback, CrowdFrame* frame) {
  CrowdFrame& f = *frame;
  const uint32_t groups = uint32_t(f.group_masks.size());
  const uint32_t buckets = lods * sub_meshes;
  f.runs.clear();
  f.run_offsets.assign(size_t(buckets) + 1, 0u);
  f.bucket_offsets.assign(size_t(buckets) + 1, 0u);
  for (uint32_t l = 0; l < lods; ++l) {
    for (uint32_t s = 0; s < sub_meshes; ++s) {
      const uint32_t b = l * sub_meshes + s;
      const uint32_t first_run = uint32_t(f.runs.size());
      uint32_t entries = 0;
      if (!fallback) {
        for (uint32_t g = 0; g < groups; ++g) {
          if (((f.group_masks[g] >> s) & 1u) == 0) continue;
          const uint32_t first = f.key_offsets[l * groups + g];
          const uint32_t count = f.key_offsets[l * groups + g + 1] - first;
          appendRun(f, first_run, first, count);
          entries += count;
        }
      } else {
        // One group per LOD in dense order: the runs of records wearing s, found by scanning.
        for (uint32_t r = f.key_offsets[l]; r < f.key_offsets[l + 1]; ++r) {
          if (((f.record_masks[r] >> s) & 1u) == 0) continue;
          appendRun(f, first_run, r, 1);
          ++entries;
        }
      }
      f.run_offsets[b + 1] = uint32_t(f.runs.size());
      f.bucket_offsets[b + 1] = f.bucket_offsets[b] + entries;
    }
  }
  f.stats.bucket_entries = f.bucket_offsets[buckets];
}

void expandBucketEntries(CrowdFrame* frame) {
  CrowdFrame& f = *frame;
  f.bucket_entries.resize(f.stats.bucket_entries);
  uint32_t* out = f.bucket_entries.data();
  for (const RecordRun& run : f.runs)
    for (uint32_t k = 0; k < run.count; ++k) *out++ = run.first + k;
  f.entries_valid = true;
}

}  // namespace si::detail
