// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "vk/vulkan_programs.h"

namespace si::vk::detail {

namespace {
using si::detail::ProgramId;
constexpr VulkanProgram kPrograms[] = {
    {ProgramId::kSkinned, VulkanKind::kShaded, false, false, "skinned"},
    {ProgramId::kDepthOnly, VulkanKind::kDepthOnly, false, false, "depth_only"},
    {ProgramId::kSkinnedMotion, VulkanKind::kMotion, false, false, "skinned_motion"},
    {ProgramId::kSkinned, VulkanKind::kShaded, true, false, "skinned_8"},
    {ProgramId::kDepthOnly, VulkanKind::kDepthOnly, true, false, "depth_only_8"},
    {ProgramId::kSkinnedMotion, VulkanKind::kMotion, true, false, "skinned_motion_8"},
    {ProgramId::kSkinned, VulkanKind::kShaded, false, true, "skinned_words"},
    {ProgramId::kSkinnedMotion, VulkanKind::kMotion, false, true, "skinned_motion_words"},
    {ProgramId::kSkinned, VulkanKind::kShaded, true, true, "skinned_8_words"},
    {ProgramId::kSkinnedMotion, VulkanKind::kMotion, true, true, "skinned_motion_8_words"},
};
constexpr size_t kProgramCount = sizeof(kPrograms) / sizeof(kPrograms[0]);
}  // namespace

Span<const VulkanProgram> vulkanPrograms() {
  return Span<const VulkanProgram>(kPrograms, kProgramCount);
}

size_t vulkanProgramIndex(VulkanKind kind, bool eight_influences, bool vertex_words) {
  const bool words = vertex_words && kind != VulkanKind::kDepthOnly;
  for (size_t k = 0; k < kProgramCount; ++k)
    if (kPrograms[k].kind == kind && kPrograms[k].eight_influences == eight_influences &&
        kPrograms[k].vertex_words == words)
      return k;
  return 0;  // Every combination is listed above.
}

si::detail::ShaderConfig vulkanShaderConfig(const VulkanProgram& program) {
  si::detail::ShaderConfig config;
  config.max_instances = kVulkanMaxInstances;
  config.max_joints = 256;
  config.eight_influences = program.eight_influences;
  config.vertex_words = program.vertex_words;
  return config;
}

}  // namespace si::vk::detail
