// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's views: each view's buffers sized by its crowd, and the passes' and the
// draw's descriptor sets over them (gpu_driven_views.h).
#include <algorithm>
#include <iterator>

#include "core/str_cat.h"
#include "gl/programs/cull_layout.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/instance_record.h"
#include "vk/gpu_driven_views.h"

namespace si::vk::detail {

using si::detail::kCommandWords;
using si::detail::kCounterWords;
using si::detail::strCat;

void GpuDrivenViews::writePassSet(VkDescriptorSet set, View* v, const CharacterResources& c,
                                  const DrivenCrowd& d, VkImageView pyramid,
                                  VkImageLayout pyramid_layout) {
  // A character without tangents: the ring stands in for the tangent ring, never read.
  const GpuBuffer* tangents = c.tangents ? &v->tangent_ring : &v->ring;
  const std::vector<VkDescriptorSetLayoutBinding>& bindings = shared_.compute_layout->bindings;
  std::vector<VkDescriptorBufferInfo> buffer_infos(bindings.size());
  VkDescriptorImageInfo pyramid_info{shared_.nearest, pyramid, pyramid_layout};
  VkDescriptorImageInfo palette{shared_.nearest, c.palette.view,
                                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  VkDescriptorImageInfo morphs{
      shared_.nearest, c.morphs.image != VK_NULL_HANDLE ? c.morphs.view : shared_.no_morphs->view,
      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  std::vector<VkWriteDescriptorSet> writes;
  for (size_t k = 0; k < bindings.size(); ++k) {
    const uint32_t b = bindings[k].binding;
    auto w = vkStruct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    w.dstSet = set;
    w.dstBinding = b;
    w.descriptorCount = 1;
    w.descriptorType = bindings[k].descriptorType;
    const GpuBuffer* buffer = b == kStateBinding                     ? &d.state
                              : b == kClipsBinding                   ? &d.clips
                              : b == kTimesBinding                   ? &d.times
                              : b == kRangesBinding                  ? &d.ranges
                              : b == kBucketInfoBinding              ? &d.bucket_info
                              : b == kEntryDataBinding               ? &v->entry_data
                              : b == kRingBinding                    ? &v->ring
                              : b == kTangentRingBinding             ? tangents
                              : b == kSourceBinding                  ? &c.vertices
                              : b == kLodVerticesBinding             ? &c.lod_vertices
                              : b == kPaletteInfoBinding             ? &c.palette_info
                              : b == kCountersBinding                ? &v->counters
                              : b == kDrivenRecordsBinding           ? &v->records
                              : b == kDrivenEntriesBinding           ? &v->entries
                              : b == kDrivenVisibleBinding           ? &v->visible
                              : b == kCommandsBinding                ? &v->commands
                              : b == kViewLodsBinding                ? &v->lods
                              : b == kDrawnBinding && shared_.motion ? &v->drawn
                              : b == kPreviousOutBinding             ? &v->previous
                              : b == kPreviousRingBinding            ? &v->previous_ring
                              : b == kOverlaysBinding                ? &d.overlays
                              : b == kLayersOutBinding               ? &v->layers
                              : b == kPreviousLayersOutBinding       ? &v->previous_layers
                              : b == kDrivenMaskBinding              ? &d.masks
                              : b == kComposeTableBinding            ? &d.compose_table
                              : b == kComposedRowsBinding            ? &v->rows
                              : b == kComposedPreviousRowsBinding    ? &v->previous_rows
                              : b == kComputeDefaultsBinding         ? shared_.ring
                                                                     : shared_.unbuilt;
    if (b == kPyramidBinding || b == kPaletteBinding || b == kMorphBinding) {
      w.pImageInfo = b == kPyramidBinding   ? &pyramid_info
                     : b == kPaletteBinding ? &palette
                                            : &morphs;
    } else {
      buffer_infos[k] = {buffer->buffer, 0,
                         b == kComputeDefaultsBinding ? kComputeDefaultsRange : VK_WHOLE_SIZE};
      w.pBufferInfo = &buffer_infos[k];
    }
    writes.push_back(w);
  }
  vkUpdateDescriptorSets(shared_.objects->device(), uint32_t(writes.size()), writes.data(), 0,
                         nullptr);
}

Status GpuDrivenViews::reshape(VkCommandBuffer cmd, View* v, uint32_t slot,
                               const CharacterResources& c, const DrivenCrowd& d,
                               const CrowdView& view) {
  retire(slot, v);
  const uint64_t capacity = d.capacity;
  const uint64_t entries = capacity * d.sub_meshes;
  // The ring: as many vertices as its bytes hold (within a storage binding), at least one
  // instance of the largest list; none asked: a one-vertex stand-in the passes never fill.
  const uint64_t ring_vertices =
      std::min<uint64_t>(shared_.ring_bytes, shared_.max_storage_range) / 16;
  if (shared_.ring_bytes != 0 && ring_vertices < c.pre_skin.max_lod_vertices)
    return {StatusCode::kLimitExceeded,
            strCat("vk::Renderer::recordGpuDrivenPasses: a ring of ", shared_.ring_bytes,
                   " bytes (RendererDesc::gpu_driven_ring_bytes) does not hold one instance of "
                   "the largest LOD (",
                   c.pre_skin.max_lod_vertices, " vertices)")};
  const uint64_t ring_slots = std::max<uint64_t>(ring_vertices, 1);
  const VkBufferUsageFlags storage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  // Layer records: one per instance, then a 2D blend's extra ones (cull.comp.glsl's u_extras);
  // composed layers' rows: the compose shape's bytes per instance.
  const uint64_t layer_records = !d.layers ? 1 : capacity * (d.extras ? 1 + kExtraLayerRecords : 1);
  const uint64_t row_bytes =
      d.extras ? std::max<uint64_t>(capacity * d.shape.recordBytes(), 16) : 16;
  const BufferNeed needs[] = {
      {&v->lods, capacity * 8, storage, "the view's LODs"},
      {&v->counters, uint64_t(kCounterWords) * 4,
       storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
       "the counters"},
      {&v->records, capacity * kInstanceRecordSize, storage, "the records"},
      {&v->visible, capacity * 16, storage, "the visible list"},
      {&v->entries, entries * 4, storage, "the bucket entries"},
      {&v->commands, uint64_t(kCommandWords) * 4, storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
       "the indirect commands"},
      {&v->entry_data, entries * 8, storage, "the pre-skinned entries"},
      {&v->ring, ring_slots * 16, storage, "the pre-skinned ring"},
      {&v->tangent_ring, c.tangents ? ring_slots * 4 : 16, storage, "the tangent ring"},
      {&v->previous, shared_.motion ? capacity * kInstanceRecordSize : 16, storage,
       "the previous records"},
      {&v->previous_ring, shared_.motion ? ring_slots * 16 : 16, storage,
       "the previous positions' ring"},
      {&v->layers, layer_records * 16, storage, "the layer records"},
      {&v->previous_layers, shared_.motion ? layer_records * 16 : 16, storage,
       "the previous layer records"},
      {&v->rows, row_bytes, storage, "the composed layers' rows"},
      {&v->previous_rows, shared_.motion ? row_bytes : 16, storage,
       "the composed layers' previous rows"}};
  Status s = createBuffers(shared_.objects, Span<const BufferNeed>(needs, std::size(needs)),
                           shared_.max_storage_range, d.capacity);
  if (!s.isOk()) {
    retire(slot, v);
    return s;
  }
  // The passes' set and the draw's.
  s = createDescriptorSet(shared_.objects->device(), shared_.objects->allocator(),
                          shared_.compute_layout->set_layout, shared_.compute_layout->bindings,
                          &v->pass_pool, &v->pass_set);
  if (!s.isOk()) {
    retire(slot, v);
    return s;
  }
  writePassSet(v->pass_set, v, c, d, shared_.no_pyramid->view,
               VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  // A character without tangents: the ring stands in for the tangent ring, never read.
  const GpuBuffer* tangents = c.tangents ? &v->tangent_ring : &v->ring;
  // The draw's set: the character's resources and the passes' output.
  const DrivenOutputs outputs{v->records, v->entries,         v->visible,  v->entry_data,
                              v->ring,    *tangents,          v->previous, v->previous_ring,
                              v->layers,  v->previous_layers, d.masks,     d.compose_table,
                              v->rows,    v->previous_rows};
  s = createCharacterSet(
      shared_.objects->device(), shared_.objects->allocator(), *shared_.draw_layout,
      {*shared_.ring, shared_.nearest, shared_.linear, *shared_.custom, *shared_.no_morphs}, c,
      &outputs, &v->draw_pool, &v->draw_set);
  // The LODs' seed: each instance's from the CPU view's (a seed: handle 0, whichever instance
  // sits there), through this slot's staging.
  if (v->staging.size() < shared_.frames_in_flight) v->staging.resize(shared_.frames_in_flight);
  GpuBuffer& staging = v->staging[slot];
  const VkDeviceSize seed_bytes = std::max<VkDeviceSize>(VkDeviceSize(d.instances) * 8, 8);
  if (s.isOk() && staging.size < seed_bytes) {
    shared_.objects->destroy(&staging);
    s = shared_.objects->createBuffer(seed_bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true,
                                      "the view's LOD seed", &staging);
  }
  if (!s.isOk()) {
    retire(slot, v);
    return s;
  }
  std::vector<uint32_t> seed;
  CrowdExport::lods(view, &seed);
  auto* kept = static_cast<uint32_t*>(staging.mapped);
  for (uint32_t k = 0; k < d.instances; ++k) {
    kept[2 * k] = 0;
    kept[2 * k + 1] = k < seed.size() ? seed[k] : 0u;
  }
  if (d.instances > 0) {
    const VkBufferCopy region{0, 0, VkDeviceSize(d.instances) * 8};
    vkCmdCopyBuffer(cmd, staging.buffer, v->lods.buffer, 1, &region);
  }
  v->crowd = &d;
  v->generation = d.generation;
  v->capacity = d.capacity;
  v->sub_meshes = d.sub_meshes;
  v->buckets = d.buckets;
  v->ring_vertices = uint32_t(ring_vertices);
  return Status::ok();
}

}  // namespace si::vk::detail
