// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's several-crowds table (--crowds N,...): N crowds of one character, each of every
// --sizes count (a crowd holds at most 2^20 instances: 10M characters of one kind are 10 crowds),
// standing side by side on one field, each stepped and drawn every frame by the GPU-driven path
// (pre-skinned). Medians of the frame's submit and GPU time (all N draws), and the renderer's
// GPU memory after the last frame (Renderer::gpuMemory): per crowd, the staging ring, in all.
#include <cstdio>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table and CSV rows "crowds" (lod: "N crowds", max_error: total MiB).
Status crowdsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                   const std::vector<uint32_t>& sizes, const std::vector<uint32_t>& crowd_counts,
                   std::FILE* csv);

}  // namespace si::bench
