// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's motion vectors table (--motion-vectors): the field drawn into a colour + motion
// + depth target (si::MotionTarget) by drawCrowd's two skinning paths (the crowd keeping its
// previous records) and drawCrowdGpuCulled's two draws (their own previous records), without and
// with motion vectors (RendererDesc::motion_vectors), side by side in one run. The baselines
// draw no motion vectors and are left out.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "motion-vectors") for every size and for the instanced,
/// compute, gpu-culled and gpu-driven paths among `paths`, with the mean and largest motion of the last frame in pixels.
Status motionVectorsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                          const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                          std::FILE* csv);

}  // namespace si::bench
