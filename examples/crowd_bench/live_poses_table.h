// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's live poses table (--live N,...): the field drawn with N of its instances posed
// live each frame (CrowdManager::setLivePoses, one batch a frame on the crowd's workers: every
// posed instance gets a new pose every frame, the worst case for the upload), beside the same
// field without live poses, side by side in one run, on drawCrowd's two skinning paths. The update
// column holds the crowd's advance, the poses set and the selection (the frame order of
// docs/crowd.md); the submit column the draw's CPU time, the live frames' upload included.
// A second table pairs frames of one crowd, posed and not, and gives what posing adds to the
// CPU as the median of the pairs' differences: the separate crowds of the first are timed
// minutes apart on a shared host, and their difference at 1,000 poses is within its drift.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "live") for every size, every count of `live` (clamped to
/// the size) and the instanced and compute paths among `paths`, drawn by a renderer made with
/// `desc` (the vertex-shader path named) holding setup.character and `palette`.
Status livePosesTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                      const std::vector<uint32_t>& sizes, const std::vector<uint32_t>& live,
                      const std::vector<std::string>& paths, std::FILE* csv);

}  // namespace si::bench
