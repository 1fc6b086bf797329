// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's layered animation table (--layers): the field drawn by drawCrowd's two
// skinning paths and the GPU-driven paths (gpu-culled: vertex-shader skinning, gpu-driven:
// pre-skinning) with no overlay, with every instance waving its right arm over its clip at
// full weight (the anchor's composition), and held half-way (weight 0.5: each link of the
// arm's chain blended in local space too), side by side in one run, with the layered error of
// each weight (si::measureLayeredError) against the local-space reference. Every path composes
// the layers (RendererDesc::compose_layers) and runs both weights again with composing off
// (each vertex walking its chains).
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"

namespace si::bench {

/// Prints the table (and CSV rows "layers") for every size and for the instanced, compute,
/// gpu-culled and gpu-driven paths among `paths`, drawn by `renderer` (holding `palette` and setup.character).
/// kNotFound when the character has no "wave" clip or "r_clavicle" joint.
Status layersTable(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                   const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                   std::FILE* csv);

}  // namespace si::bench
