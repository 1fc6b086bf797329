// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A program of the back-end on the host's device: its stages' shader modules (a vertex and a
// fragment stage, or a compute stage), made from the embedded SPIR-V (spirv_modules.h), and what
// each declares (spirv_reflect.h).

#include <vulkan/vulkan.h>

#include "si/core/status.h"
#include "vk/spirv_reflect.h"

namespace si::vk::detail {

struct ProgramModules {
  SpirvReflection vertex_reflection, fragment_reflection, compute_reflection;
  VkShaderModule vertex_module = VK_NULL_HANDLE, fragment_module = VK_NULL_HANDLE;
  VkShaderModule compute_module = VK_NULL_HANDLE;
};

/// Program `name`'s stages ("<name>.vert" and "<name>.frag", or "<name>.comp" when `compute`),
/// read and made into modules on `device`. kNotFound when they are not embedded; kUnsupported
/// naming a default uniform past the `defaults_range` bytes its block is given; the reader's and
/// kBackend's codes otherwise. What was made is in `out` either way (destroyProgramModules
/// frees it).
Status loadProgramModules(VkDevice device, const VkAllocationCallbacks* allocator, const char* name,
                          bool compute, VkDeviceSize defaults_range, ProgramModules* out);
/// Destroys `p`'s modules.
void destroyProgramModules(VkDevice device, const VkAllocationCallbacks* allocator,
                           ProgramModules* p);

}  // namespace si::vk::detail
