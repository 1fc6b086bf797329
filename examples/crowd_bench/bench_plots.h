// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench --plots DIR: the frame time against crowd size and the GPU time against bake
// error, as a gnuplot script run when gnuplot is installed.
#include <cstdint>
#include <map>
#include <string>

namespace si::bench {

/// Writes DIR/plot.gp for `folder` (frame_time.png from `frame_ms`, max(CPU, GPU) ms per frame
/// by "path/lod" and size on `scene`; gpu_vs_error.png from `error_data`, the bake table's
/// "error ms label" lines) and runs gnuplot on it; false (saying why) when the script cannot
/// be written or gnuplot is missing or fails.
bool writePlots(const std::string& folder, const std::string& scene,
                const std::map<std::string, std::map<uint32_t, double>>& frame_ms,
                const std::string& error_data);

}  // namespace si::bench
