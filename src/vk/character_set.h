// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A character's descriptor set: every binding of the programs' one set layout filled, with the
// character's buffers and images or what the renderer shares (the record ring at each block's
// range, the samplers, the placeholders for what a character has none of).

#include <vulkan/vulkan.h>

#include "si/core/status.h"
#include "vk/character_resources.h"
#include "vk/device_objects.h"
#include "vk/skinned_pipeline.h"

namespace si::vk::detail {

/// What every character's set binds of the renderer's.
struct SharedResources {
  const GpuBuffer& ring;      ///< The record ring.
  VkSampler nearest, linear;  ///< The palette's and morphs' sampler, the materials'.
  const GpuImage& custom;     ///< The custom texture array's placeholder.
  const GpuImage& no_morphs;  ///< The morph image of characters without targets.
};

/// What a GPU-driven draw reads of its view's passes (gpu_driven_layout.h's bindings).
struct DrivenOutputs {
  const GpuBuffer& records;
  const GpuBuffer& entries;
  const GpuBuffer& visible;
  const GpuBuffer& entry_data;    ///< Each pre-skinned entry's ring base and list.
  const GpuBuffer& ring;          ///< The pre-skinned vertices.
  const GpuBuffer& tangent_ring;  ///< Their tangents (the ring stands in without).
  const GpuBuffer& previous;      ///< Motion vectors: each visible instance's previous record,
  const GpuBuffer& previous_ring;  ///< and the pre-skinned previous positions.
  /// Layered animation: each visible instance's layer record and previous layer record, and the
  /// crowd's layer mask table (placeholders for a crowd without overlays).
  const GpuBuffer& layers;
  const GpuBuffer& previous_layers;
  const GpuBuffer& masks;
  /// Composed layers (2D blends): the crowd's compose table, the rows composed per visible
  /// instance and the previous ones (placeholders without).
  const GpuBuffer& compose_table;
  const GpuBuffer& rows;
  const GpuBuffer& previous_rows;
};

/// Creates a descriptor pool and its one set for `layout` into `*pool` and `*set` and writes
/// every binding with `c`'s resources, `shared`'s, and for the GPU-driven draw's layout
/// `driven`'s (may be null for the others). kBackend naming the failed call (what was made stays
/// in `*pool`, for the caller to destroy).
Status createCharacterSet(VkDevice device, const VkAllocationCallbacks* allocator,
                          const SkinnedLayout& layout, const SharedResources& shared,
                          const CharacterResources& c, const DrivenOutputs* driven,
                          VkDescriptorPool* pool, VkDescriptorSet* set);

}  // namespace si::vk::detail
