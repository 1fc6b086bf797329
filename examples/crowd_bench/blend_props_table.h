// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's blend spaces and props table (--blend): the field with every instance playing
// its clip (plain), blending the walk and the run (a 1D blend space on a full-body mask, each at
// its own parameter), blending four clips (a 2D space: a 2 x 2 grid, each at its own point
// inside the cell), holding a staff (a prop read from the sample RiggedSimple at a right-hand
// socket, its LOD chain built to the character's levels), and the two-clip blend with the staff,
// side by side in one run, drawn by drawCrowd's two skinning paths and the GPU-driven paths.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "blend") for every size and for the instanced, compute,
/// gpu-culled and gpu-driven paths among `paths`, drawn by a renderer made with `desc` (the
/// vertex-shader path named) holding setup.character with the staff. kNotFound when the
/// character has no 'walk' and 'run' clips or 'r_hand' joint.
Status blendPropsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                       const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                       std::FILE* csv);

}  // namespace si::bench
