// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's views table (--views): one main view and N - 1 shadow cascades per frame. The
// crowd advances once (CrowdManager::advance), each view selects for its own camera
// (si::CrowdView; cascades one LOD coarser, no far line) and is drawn: the main view in colour,
// each cascade depth-only from an orthographic sun camera fitted round its slice of the main
// camera's frustum. Side by side with 1 view in the same run.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "views") for every size, view count and path among
/// `paths` that selects on the CPU (instanced, compute, traditional, cpu, rigid; the GPU-driven
/// paths are listed as not taking views yet). `view_counts` holds 1 and more (1: main only).
Status viewsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                  const std::vector<uint32_t>& sizes, const std::vector<uint32_t>& view_counts,
                  const std::vector<std::string>& paths, uint32_t max_baseline, std::FILE* csv);

}  // namespace si::bench
