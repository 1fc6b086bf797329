// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The impostor atlas's passes and the GPU-driven impostors': their layouts and pipelines.
#include "vk/impostor_passes.h"

#include "si_vk/vulkan_profile.h"
#include "vk/device_objects.h"
#include "vk/vulkan_programs.h"

namespace si::vk::detail {

bool impostorQuadsBindingType(uint32_t b, DescriptorKind kind, VkDescriptorType* type) {
  const bool storage = b == kCountersBinding || b == kDrivenRecordsBinding ||
                       b == kDrivenEntriesBinding || b == kDrivenVisibleBinding ||
                       b == kCommandsBinding || b == kImpostorClipsBinding ||
                       b == kImpostorQuadsBinding;
  if (storage && kind == DescriptorKind::kStorageBuffer)
    *type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  else if (b == kComputeDefaultsBinding && kind == DescriptorKind::kUniformBuffer)
    *type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
  else
    return false;
  return true;
}

bool impostorCoverageBindingType(uint32_t b, DescriptorKind kind, VkDescriptorType* type) {
  if ((b == kImpostorQuadsBinding || b == kImpostorClipsBinding) &&
      kind == DescriptorKind::kStorageBuffer)
    *type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  else if (b == kImpostorAtlasBinding && kind == DescriptorKind::kCombinedImageSampler)
    *type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  else if (b == kComputeDefaultsBinding && kind == DescriptorKind::kUniformBuffer)
    *type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
  else
    return false;
  return true;
}

bool impostorResolveBindingType(uint32_t b, DescriptorKind kind, VkDescriptorType* type) {
  if (b == kResolveCaptureBinding && kind == DescriptorKind::kCombinedImageSampler)
    *type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  else if (b == kResolveAtlasBinding && kind == DescriptorKind::kStorageImage)
    *type = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  else if (b == kComputeDefaultsBinding && kind == DescriptorKind::kUniformBuffer)
    *type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
  else
    return false;
  return true;
}

Status createAtlasSampler(VkDevice device, const VkAllocationCallbacks* allocator, float lod_bias,
                          VkSampler* out) {
  auto info = vkStruct<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
  info.magFilter = info.minFilter = VK_FILTER_LINEAR;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.mipLodBias = lod_bias;
  info.maxLod = VK_LOD_CLAMP_NONE;
  return checkVk(vkCreateSampler(device, &info, allocator, out),
                 "vkCreateSampler (the impostor atlas's)");
}

Status createImpostorPasses(VkDevice device, const VkAllocationCallbacks* allocator,
                            const std::vector<ProgramModules>& programs,
                            const RenderingFormats& shaded, const RenderingFormats& depth_only,
                            ImpostorPasses* out) {
  out->quads_program = &programs[vulkanComputeProgramIndex(si::detail::ProgramId::kImpostorQuads)];
  Status s = createComputeLayout(
      device, allocator, Span<const ProgramModules* const>(&out->quads_program, 1),
      impostorQuadsBindingType, "the impostor quads pass", &out->quads_layout);
  if (s.isOk())
    s = createComputePipeline(device, allocator, *out->quads_program,
                              out->quads_layout.pipeline_layout, &out->quads);
  if (s.isOk()) s = createAtlasSampler(device, allocator, 0.0f, &out->sampler);
  const si::detail::ProgramId coverage_ids[2] = {si::detail::ProgramId::kImpostorCoverage,
                                                 si::detail::ProgramId::kImpostorCoverageRects};
  for (int k = 0; k < 2; ++k)
    out->coverage_programs[k] = &programs[vulkanComputeProgramIndex(coverage_ids[k])];
  if (s.isOk())
    s = createComputeLayout(
        device, allocator, Span<const ProgramModules* const>(out->coverage_programs, 2),
        impostorCoverageBindingType, "the impostor coverage passes", &out->coverage_layout);
  for (int k = 0; k < 2 && s.isOk(); ++k)
    s = createComputePipeline(device, allocator, *out->coverage_programs[k],
                              out->coverage_layout.pipeline_layout, &out->coverage[k]);
  out->resolve_program =
      &programs[vulkanComputeProgramIndex(si::detail::ProgramId::kImpostorResolve)];
  if (s.isOk())
    s = createComputeLayout(
        device, allocator, Span<const ProgramModules* const>(&out->resolve_program, 1),
        impostorResolveBindingType, "the impostor resolve pass", &out->resolve_layout);
  if (s.isOk())
    s = createComputePipeline(device, allocator, *out->resolve_program,
                              out->resolve_layout.pipeline_layout, &out->resolve);
  std::vector<StageReflection> stages;
  for (int k = 0; k < 2; ++k) {
    out->draw_programs[k] = &programs[vulkanImpostorProgramIndex(k == 1)];
    stages.push_back({VK_SHADER_STAGE_VERTEX_BIT, &out->draw_programs[k]->vertex_reflection});
    stages.push_back({VK_SHADER_STAGE_FRAGMENT_BIT, &out->draw_programs[k]->fragment_reflection});
  }
  if (s.isOk())
    s = createSkinnedLayout(device, allocator,
                            Span<const StageReflection>(stages.data(), stages.size()),
                            &out->draw_layout);
  for (int k = 0; k < 2 && s.isOk(); ++k)
    s = createImpostorPipeline(device, allocator, *out->draw_programs[k],
                               out->draw_layout.pipeline_layout, k == 0 ? shaded : depth_only,
                               &out->draws[k]);
  return s;
}

void destroyImpostorPasses(VkDevice device, const VkAllocationCallbacks* allocator,
                           ImpostorPasses* passes) {
  for (VkPipeline p : {passes->quads, passes->draws[0], passes->draws[1], passes->coverage[0],
                       passes->coverage[1], passes->resolve})
    if (p != VK_NULL_HANDLE) vkDestroyPipeline(device, p, allocator);
  if (passes->sampler != VK_NULL_HANDLE) vkDestroySampler(device, passes->sampler, allocator);
  destroyComputeLayout(device, allocator, &passes->quads_layout);
  destroyComputeLayout(device, allocator, &passes->coverage_layout);
  destroyComputeLayout(device, allocator, &passes->resolve_layout);
  SkinnedLayout& l = passes->draw_layout;
  if (l.pipeline_layout != VK_NULL_HANDLE)
    vkDestroyPipelineLayout(device, l.pipeline_layout, allocator);
  if (l.set_layout != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device, l.set_layout, allocator);
  *passes = ImpostorPasses();
}

}  // namespace si::vk::detail
