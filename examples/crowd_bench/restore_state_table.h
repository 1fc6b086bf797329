// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's state contract table (--restore-state): what saving and restoring the host's GL
// state costs (RendererDesc::restore_state). Each frame of the field is drawn twice by the same
// renderer, restore off then on, so both columns see the same crowd, camera and machine load;
// the medians over the frames and the difference, in microseconds and as a share of the frame.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "restore-state") for every size and path among `paths`
/// (instanced, compute, gpu-culled, gpu-driven and their -occlusion variants, traditional,
/// cpu, rigid).
Status restoreStateTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                         const std::vector<uint32_t>& sizes,
                         const std::vector<std::string>& paths, std::FILE* csv);

}  // namespace si::bench
