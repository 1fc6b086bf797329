// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A character's descriptor set.
#include "vk/character_set.h"

#include <vector>

#include "vk/gpu_driven_layout.h"

namespace si::vk::detail {

Status createCharacterSet(VkDevice device, const VkAllocationCallbacks* allocator,
                          const SkinnedLayout& layout, const SharedResources& shared,
                          const CharacterResources& character, const DrivenOutputs* driven,
                          VkDescriptorPool* pool, VkDescriptorSet* set) {
  const CharacterResources* c = &character;
  Status s = createDescriptorSet(device, allocator, layout.set_layout, layout.bindings, pool, set);
  if (!s.isOk()) return s;
  std::vector<VkDescriptorBufferInfo> buffer_infos(layout.bindings.size());
  std::vector<VkDescriptorImageInfo> image_infos(layout.bindings.size());
  std::vector<VkWriteDescriptorSet> writes;
  for (size_t k = 0; k < layout.bindings.size(); ++k) {
    const uint32_t b = layout.bindings[k].binding;
    auto w = vkStruct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    w.dstSet = *set;
    w.dstBinding = b;
    w.descriptorCount = 1;
    w.descriptorType = layout.bindings[k].descriptorType;
    const auto buffer = [&](const GpuBuffer& g, VkDeviceSize range) {
      buffer_infos[k] = {g.buffer, 0, range};
      w.pBufferInfo = &buffer_infos[k];
    };
    const auto image = [&](const GpuImage& g, VkSampler sampler) {
      image_infos[k] = {sampler, g.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
      w.pImageInfo = &image_infos[k];
    };
    if (b == kRecordsBinding)
      buffer(shared.ring, kRecordsRange);
    else if (b == kVertexDefaultsBinding || b == kFragmentDefaultsBinding)
      buffer(shared.ring, kDefaultsRange);
    else if (b == kPaletteInfoBinding)
      buffer(c->palette_info, VK_WHOLE_SIZE);
    else if (b == kVertexMaterialsBinding)
      buffer(c->vertex_materials, VK_WHOLE_SIZE);
    else if (b == kMaterialTableBinding)
      buffer(c->materials, VK_WHOLE_SIZE);
    else if (b == kPreviousBinding)
      buffer(shared.ring, VK_WHOLE_SIZE);
    else if (b == kLayersBinding || b == kPreviousLayersBinding)
      buffer(shared.ring, kLayersRange);
    else if (b == kMaskBinding)
      buffer(shared.ring, kMaskRange);
    else if (b == kPaletteBinding)
      image(c->palette, shared.nearest);
    else if (b == kBaseColorBinding)
      image(c->base_color, shared.linear);
    else if (b == kCustomBinding)
      image(shared.custom, shared.linear);
    else if (b == kMaterialDataBinding)
      image(c->material_data, shared.linear);
    else if (b == kMorphBinding)
      image(c->morphs.image != VK_NULL_HANDLE ? c->morphs : shared.no_morphs, shared.nearest);
    else if (driven != nullptr && b == kDrivenRecordsBinding)
      buffer(driven->records, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kDrivenEntriesBinding)
      buffer(driven->entries, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kDrivenVisibleBinding)
      buffer(driven->visible, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kEntryDataBinding)
      buffer(driven->entry_data, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kRingBinding)
      buffer(driven->ring, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kTangentRingBinding)
      buffer(driven->tangent_ring, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kPreviousOutBinding)
      buffer(driven->previous, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kPreviousRingBinding)
      buffer(driven->previous_ring, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kLayersOutBinding)
      buffer(driven->layers, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kPreviousLayersOutBinding)
      buffer(driven->previous_layers, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kDrivenMaskBinding)
      buffer(driven->masks, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kComposeTableBinding)
      buffer(driven->compose_table, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kComposedRowsBinding)
      buffer(driven->rows, VK_WHOLE_SIZE);
    else if (driven != nullptr && b == kComposedPreviousRowsBinding)
      buffer(driven->previous_rows, VK_WHOLE_SIZE);
    else if (b == kSourceBinding)
      buffer(c->vertices, VK_WHOLE_SIZE);
    else if (b == kLodVerticesBinding)
      buffer(c->lod_vertices, VK_WHOLE_SIZE);
    writes.push_back(w);
  }
  vkUpdateDescriptorSets(device, uint32_t(writes.size()), writes.data(), 0, nullptr);
  return Status::ok();
}

}  // namespace si::vk::detail
