// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's materials table (--materials): what drawing through a host material costs
// (si::MaterialDesc, Renderer::setMaterial). Each frame of the field is drawn twice by the same
// renderer, with the built-in material (glTF metallic-roughness) and then with a host material
// computing the library's former look (Lambert over a constant ambient) from a uniform block of
// its own, so both columns see the same crowd, camera and machine load; the medians over the
// frames and their ratios.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "materials", lod column "builtin" or "host") for every size
/// and path among `paths` (instanced, compute, gpu-culled, gpu-driven and their -occlusion
/// variants, traditional, cpu, rigid).
Status materialsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                      const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                      std::FILE* csv);

}  // namespace si::bench
