// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's state uploads table (--moving F,...): what the GPU-driven path pays when a
// share F of the crowd moves every frame (setTransform on every 1/F-th instance), uploading only
// the instances that changed (RendererDesc::gpu_state_upload kChanged, the default) against
// uploading every instance at any change (kWhole). Both renderers draw each frame of the same
// crowd in turn; medians of the CPU's submit (export and upload included), the bytes uploaded
// and the GPU time.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table for every size and share moved, and CSV rows "uploads" (one per side: the
/// visible column holds the instances moved, update_ms the moves, rate the share, max_error the
/// MiB uploaded, lod "changed" or "whole").
Status uploadsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                    const std::vector<uint32_t>& sizes, const std::vector<double>& shares,
                    std::FILE* csv);

}  // namespace si::bench
