// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's root motion table (--root-motion): the field playing the embedded character's
// travelling clips in place against the same crowd moved by their root motion
// (InstanceDesc::root_motion), each path side by side in one run. With root motion the
// GPU-selected paths call update() every frame (the crowd moves instances only there) and
// re-upload the moved state.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "root-motion") for every size and path; `setup.character`
/// (the embedded character with its LOD chain) is given its travelling clips, baked at 30 Hz.
Status rootMotionTable(Setup& setup, const RendererDesc& desc, const std::vector<uint32_t>& sizes,
                       const std::vector<std::string>& paths, uint32_t max_baseline,
                       std::FILE* csv);

}  // namespace si::bench
