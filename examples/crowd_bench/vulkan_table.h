// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's Vulkan table (--vulkan): the vertex-shader path drawn by si::gl (drawCrowd, on
// the bench's OpenGL context) and by si::vk (recordDraw into the frame of the vulkan_host
// example's headless Vulkan host, the same size), side by side in one run: each frame the same
// crowd, camera and selection drawn by both, one after the other. GL's GPU time is its timer
// query (RendererDesc::measure_gpu_time), Vulkan's the host's timestamps around the recorded
// draws; the last frames' images are compared.
#include <cstdio>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "vulkan") for every size, the crowd selecting its levels by
/// `lod`. kUnsupported when crowd_bench was built without si::vk or the machine has no Vulkan
/// 1.3 device.
Status vulkanTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                   const std::vector<uint32_t>& sizes, const LodChoice& lod, std::FILE* csv);

}  // namespace si::bench
