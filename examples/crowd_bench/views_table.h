// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's views table (--views): one main view and N - 1 shadow cascades per frame. The
// crowd advances once (CrowdManager::advance), each view selects for its own camera
// (si::CrowdView; cascades `cascade_lod_bias` LODs coarser, no far line) and is drawn: the main
// view in colour, each cascade depth-only from an orthographic sun camera fitted round its slice
// of the main camera's frustum. On the GPU-driven paths the crowd advances its clock only and
// each view selects on the GPU. Side by side with 1 view in the same run.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "views") for every size, view count and path among `paths`,
/// the crowd selecting its levels by `lod` (the first --lods choice).
/// `view_counts` holds 1 and more (1: main only); `cascade_lod_bias` is 0 to 7. With
/// `desc.measure_gpu_passes`, also each row's GPU time per pass (a frame's views summed), its
/// CSV at `passes_csv`.
Status viewsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                  const std::vector<uint32_t>& sizes, const std::vector<uint32_t>& view_counts,
                  uint32_t cascade_lod_bias, const LodChoice& lod,
                  const std::vector<std::string>& paths, uint32_t max_baseline, std::FILE* csv,
                  const std::string& passes_csv);

}  // namespace si::bench
