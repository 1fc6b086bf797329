// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's churn table (--churn F,...): a share F of the crowd removed and as many added
// every frame (a spawn and despawn wave at a steady size), drawn by the GPU-driven path
// (pre-skinned) in 4 views (the main view and 3 shadow cascades, depth-only). Medians of the
// CPU's churn (remove and add), the 4 draws' submit (uploads and re-seeding included), the
// MiB uploaded and the GPU time, against the same crowd without churn.
#include <cstdio>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table and CSV rows "churn" (update_ms: the churn, rate: the share, max_error: MiB).
Status churnTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                  const std::vector<uint32_t>& sizes, const std::vector<double>& shares,
                  std::FILE* csv);

}  // namespace si::bench
