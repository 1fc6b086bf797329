// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The Vulkan back-end's programs.
#include "vk/vulkan_programs.h"

namespace si::vk::detail {

Span<const VulkanProgram> vulkanPrograms() {
  static const VulkanProgram kPrograms[] = {
      {si::detail::ProgramId::kSkinned, "skinned"},
      {si::detail::ProgramId::kDepthOnly, "depth_only"},
      {si::detail::ProgramId::kSkinnedMotion, "skinned_motion"},
  };
  return Span<const VulkanProgram>(kPrograms, sizeof(kPrograms) / sizeof(kPrograms[0]));
}

si::detail::ShaderConfig vulkanShaderConfig() {
  si::detail::ShaderConfig config;
  config.max_instances = kVulkanMaxInstances;
  config.max_joints = 256;
  return config;
}

}  // namespace si::vk::detail
