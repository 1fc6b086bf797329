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

/// Creates `c`'s descriptor pool and set for `layout` and writes every binding. kBackend naming
/// the failed call (what was made stays in `c`, for destroyCharacter).
Status createCharacterSet(VkDevice device, const VkAllocationCallbacks* allocator,
                          const SkinnedLayout& layout, const SharedResources& shared,
                          CharacterResources* c);

}  // namespace si::vk::detail
