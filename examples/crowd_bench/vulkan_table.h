// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's Vulkan table (--vulkan): vertex-shader skinning drawn by si::gl (on the bench's
// OpenGL context) and by si::vk (into the frame of the vulkan_host example's headless Vulkan
// host, the same size), side by side in one run: each frame the same crowd and camera drawn by
// both, one after the other, on the instanced path (drawCrowd, recordDraw: the CPU's selection)
// and the GPU-driven one (drawCrowdGpuCulled, recordGpuDrivenPasses and recordGpuDrivenDraw:
// "gpu-culled" skinning in the vertex stage, "gpu-driven" pre-skinning in compute first). GL's GPU
// time is its timer query (RendererDesc::measure_gpu_time), Vulkan's the host's timestamps around
// the recorded passes and draws; the last frames' images are compared.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints a table per scene of `scenes` (and CSV rows "vulkan") for every size and each of
/// `paths` the Vulkan back-end draws (instanced, gpu-culled, gpu-driven, the last two also with
/// "-occlusion"; the others are named as not built), the crowd selecting its levels by `lod`.
/// kUnsupported when crowd_bench was built without si::vk or the machine has no Vulkan 1.3
/// device.
Status vulkanTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                   const std::vector<std::string>& scenes, const std::vector<uint32_t>& sizes,
                   const std::vector<std::string>& paths, const LodChoice& lod, std::FILE* csv);

}  // namespace si::bench
