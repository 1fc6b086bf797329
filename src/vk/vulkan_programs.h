// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The Vulkan back-end's programs: which programs of si::gl's catalog it builds, and the shader
// configuration they are assembled with (the same files, defines and catalog; glslang defines
// VULKAN, which si_profile.glsl reads). Used at build time by the step that writes their GLSL
// (tools/write_vulkan_glsl.cpp) and at run time to name the embedded SPIR-V. No Vulkan here.

#include "gl/programs/program_catalog.h"
#include "si/core/span.h"

namespace si::vk::detail {

/// One program of the back-end: the catalog's program and the name its SPIR-V files take.
struct VulkanProgram {
  si::detail::ProgramId id;
  const char* name;
};

/// The programs the Vulkan back-end builds so far: the vertex-shader path, shaded and depth only.
Span<const VulkanProgram> vulkanPrograms();

/// Records in the instance uniform block: 819 of 80 bytes fill a 64 KiB block, the
/// maxUniformBufferRange of NVIDIA's and lavapipe's drivers (the Vulkan minimum is 16 KiB: a
/// device below 64 KiB is refused by name).
inline constexpr uint32_t kVulkanMaxInstances = 819;

/// The configuration the programs are assembled with.
si::detail::ShaderConfig vulkanShaderConfig();

}  // namespace si::vk::detail
