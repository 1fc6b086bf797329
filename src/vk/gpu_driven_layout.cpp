// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven compute passes' layouts and pipelines.
#include "vk/gpu_driven_layout.h"

#include <map>

#include "core/str_cat.h"
#include "vk/device_objects.h"
#include "vk/skinned_pipeline.h"

namespace si::vk::detail {

using si::detail::strCat;

bool drivenPassBindingType(uint32_t b, DescriptorKind kind, VkDescriptorType* type) {
  const bool storage =
      b == kStateBinding || b == kClipsBinding || b == kTimesBinding || b == kCountersBinding ||
      b == kDrivenRecordsBinding || b == kDrivenEntriesBinding || b == kDrivenVisibleBinding ||
      b == kCommandsBinding || b == kRangesBinding || b == kBucketInfoBinding ||
      b == kEntryDataBinding || b == kViewLodsBinding || b == kOverlaysBinding ||
      b == kLayersOutBinding || b == kDrawnBinding || b == kPreviousOutBinding ||
      b == kPreviousLayersOutBinding || b == kDrivenMaskBinding || b == kLivePosesBinding ||
      b == kRingBinding || b == kSourceBinding || b == kLodVerticesBinding ||
      b == kTangentRingBinding || b == kPreviousRingBinding || b == kComposeTableBinding ||
      b == kComposedRowsBinding || b == kComposedPreviousRowsBinding;
  if (storage && kind == DescriptorKind::kStorageBuffer)
    *type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  else if (b == kComputeDefaultsBinding && kind == DescriptorKind::kUniformBuffer)
    *type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
  else if (b == kPaletteInfoBinding && kind == DescriptorKind::kUniformBuffer)
    *type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  else if ((b == kPyramidBinding || b == kPaletteBinding || b == kMorphBinding) &&
           kind == DescriptorKind::kCombinedImageSampler)
    *type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  else
    return false;
  return true;
}

Status createComputeLayout(VkDevice device, const VkAllocationCallbacks* allocator,
                           Span<const ProgramModules* const> passes, ComputeBindingType type_of,
                           const char* what, ComputeLayout* out) {
  std::map<uint32_t, VkDescriptorSetLayoutBinding> bindings;
  for (const ProgramModules* pass : passes)
    for (const SpirvDescriptor& d : pass->compute_reflection.descriptors) {
      VkDescriptorType type;
      if (!type_of(d.binding, d.kind, &type))
        return {StatusCode::kUnsupported,
                strCat(what, "' ", descriptorKindName(d.kind), " '", d.name, "' at binding ",
                       d.binding, " is one the Vulkan renderer does not fill")};
      bindings.emplace(d.binding, VkDescriptorSetLayoutBinding{
                                      d.binding, type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    }
  out->bindings.clear();
  for (const auto& [b, binding] : bindings) out->bindings.push_back(binding);
  return createSetLayouts(device, allocator, out->bindings, &out->set_layout,
                          &out->pipeline_layout);
}

void destroyComputeLayout(VkDevice device, const VkAllocationCallbacks* allocator,
                          ComputeLayout* layout) {
  if (layout->pipeline_layout != VK_NULL_HANDLE)
    vkDestroyPipelineLayout(device, layout->pipeline_layout, allocator);
  if (layout->set_layout != VK_NULL_HANDLE)
    vkDestroyDescriptorSetLayout(device, layout->set_layout, allocator);
  *layout = ComputeLayout();
}

Status createComputePipeline(VkDevice device, const VkAllocationCallbacks* allocator,
                             const ProgramModules& pass, VkPipelineLayout layout, VkPipeline* out) {
  auto info = vkStruct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  info.stage = vkStruct<VkPipelineShaderStageCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = pass.compute_module;
  info.stage.pName = "main";
  info.layout = layout;
  return checkVk(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, allocator, out),
                 "vkCreateComputePipelines");
}

}  // namespace si::vk::detail
