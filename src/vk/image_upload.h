// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Images filled from a staging buffer, recorded into the host's command buffer: the copy, the
// mip chain blitted level by level (as glGenerateMipmap filters it), the layout transitions to
// the shaders' reads; and the image and memory barriers every recording of the back-end (and
// the tests' host) records.

#include <vulkan/vulkan.h>

#include <cstdint>

#include "vk/device_objects.h"

namespace si::vk::detail {

/// Levels of a full mip chain of a `w` x `h` image.
uint32_t mipLevels(uint32_t w, uint32_t h);

/// One layout transition of an image barrier, with what must finish before and wait after it.
struct LayoutChange {
  VkImageLayout from, to;
  VkAccessFlags src_access, dst_access;
  VkPipelineStageFlags src, dst;
};

/// Records a global memory barrier: `src_access` of the `src` stages before `dst_access` of
/// the `dst` stages (accesses 0: an execution dependency alone).
void recordMemoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                         VkPipelineStageFlags dst, VkAccessFlags dst_access);

/// Records the barrier of `change` on levels [`level`, `level + levels`) and the first `layers`
/// layers of `image`'s `aspect`.
void recordImageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                        uint32_t level, uint32_t levels, uint32_t layers,
                        const LayoutChange& change);

/// An image's contents waiting in a staging buffer from `offset`: its layers of level 0,
/// tightly packed, and whether a mip chain is blitted from them.
struct ImageUpload {
  GpuImage* image;
  VkDeviceSize offset;
  bool mips;
};

/// Records `img`'s mip chain, each level blitted from the one above (linear filter), level 0 in
/// VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL with its contents written and the others in that layout;
/// every level is left in VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL for the `readers` stages.
void recordMipChain(VkCommandBuffer cmd, const GpuImage& img, VkPipelineStageFlags readers);

/// Records `u`'s copy from `staging`, its mip chain when it has one, and the transitions that
/// leave every level in VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL for the vertex and fragment
/// shaders' reads (the image's earlier contents discarded).
void recordImageUpload(VkCommandBuffer cmd, VkBuffer staging, const ImageUpload& u);

}  // namespace si::vk::detail
