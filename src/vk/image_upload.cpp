// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Images filled from staging, and image barriers.
#include "vk/image_upload.h"

#include <algorithm>
#include <cmath>

namespace si::vk::detail {

uint32_t mipLevels(uint32_t w, uint32_t h) {
  return uint32_t(std::floor(std::log2(double(std::max(w, h))))) + 1;
}

void recordImageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                        uint32_t level, uint32_t levels, uint32_t layers,
                        const LayoutChange& change) {
  auto b = vkStruct<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
  b.srcAccessMask = change.src_access;
  b.dstAccessMask = change.dst_access;
  b.oldLayout = change.from;
  b.newLayout = change.to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {aspect, level, levels, 0, layers};
  vkCmdPipelineBarrier(cmd, change.src, change.dst, 0, 0, nullptr, 0, nullptr, 1, &b);
}

void recordMemoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                         VkPipelineStageFlags dst, VkAccessFlags dst_access) {
  auto b = vkStruct<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &b, 0, nullptr, 0, nullptr);
}

void recordMipChain(VkCommandBuffer cmd, const GpuImage& img, VkPipelineStageFlags readers) {
  const auto barrier = [&](uint32_t level, uint32_t levels, VkImageLayout from, VkImageLayout to,
                           VkAccessFlags src_access, VkAccessFlags dst_access,
                           VkPipelineStageFlags src, VkPipelineStageFlags dst) {
    recordImageBarrier(cmd, img.image, VK_IMAGE_ASPECT_COLOR_BIT, level, levels, img.layers,
                       {from, to, src_access, dst_access, src, dst});
  };
  // Each level from the one above, filtered (as glGenerateMipmap); every level then a source.
  for (uint32_t level = 1; level < img.levels; ++level) {
    barrier(level - 1, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkImageBlit blit{};
    blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level - 1, 0, img.layers};
    blit.srcOffsets[1] = {int32_t(std::max(1u, img.width >> (level - 1))),
                          int32_t(std::max(1u, img.height >> (level - 1))), 1};
    blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, 0, img.layers};
    blit.dstOffsets[1] = {int32_t(std::max(1u, img.width >> level)),
                          int32_t(std::max(1u, img.height >> level)), 1};
    vkCmdBlitImage(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, img.image,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
  }
  if (img.levels > 1) {
    barrier(img.levels - 1, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_PIPELINE_STAGE_TRANSFER_BIT);
    barrier(0, img.levels, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_READ_BIT,
            VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, readers);
  } else {
    barrier(0, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
            VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
            readers);
  }
}

void recordImageUpload(VkCommandBuffer cmd, VkBuffer staging, const ImageUpload& u) {
  const GpuImage& img = *u.image;
  recordImageBarrier(cmd, img.image, VK_IMAGE_ASPECT_COLOR_BIT, 0, img.levels, img.layers,
                     {VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                      VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT});
  VkBufferImageCopy copy{};
  copy.bufferOffset = u.offset;
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, img.layers};
  copy.imageExtent = {img.width, img.height, 1};
  vkCmdCopyBufferToImage(cmd, staging, img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  recordMipChain(cmd, img,
                 VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
}

}  // namespace si::vk::detail
