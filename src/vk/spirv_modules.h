// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The Vulkan back-end's SPIR-V, compiled at build time by glslangValidator from the GLSL that
// tools/write_vulkan_glsl.cpp assembles (src/vk/CMakeLists.txt says with which options) and
// embedded by cmake/embed_spirv.cmake. No Vulkan here.

#include <cstddef>
#include <cstdint>

#include "si/core/span.h"

namespace si::vk::detail {

/// One module: "<program>.<stage>" (stage "vert" or "frag", vulkan_programs.h's names) and its
/// words.
struct SpirvModule {
  const char* name;
  const uint32_t* words;
  size_t word_count;
};

extern const SpirvModule kSpirvModules[];
extern const size_t kSpirvModuleCount;

/// The module named `name`, or null.
const SpirvModule* findSpirvModule(const char* name);

}  // namespace si::vk::detail
