// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "vk/frame_slots.h"

#include <cstring>

#include "core/str_cat.h"

namespace si::vk::detail {

using si::detail::strCat;

Status FrameRegion::take(VkDeviceSize size, VkDeviceSize* at) {
  const VkDeviceSize from = alignUp(*used, alignment);
  if (from + size > bytes)
    return {StatusCode::kLimitExceeded,
            strCat("vk::Renderer: the frame's records and uniforms need ", from + size,
                   " bytes, RendererDesc::ring_bytes_per_frame is ", bytes)};
  *used = from + size;
  std::memset(mapped + start + from, 0, size_t(size));
  *at = start + from;
  return Status::ok();
}

void FrameRetirement::retire(uint32_t slot, GpuBuffer* b) {
  if (b->buffer != VK_NULL_HANDLE) slots_[slot].buffers.push_back(*b);
  *b = GpuBuffer();
}

void FrameRetirement::retire(uint32_t slot, VkDescriptorPool* pool) {
  if (*pool != VK_NULL_HANDLE) slots_[slot].pools.push_back(*pool);
  *pool = VK_NULL_HANDLE;
}

void FrameRetirement::retire(uint32_t slot, GpuImage* i) {
  if (i->image != VK_NULL_HANDLE) slots_[slot].images.push_back(*i);
  *i = GpuImage();
}

void FrameRetirement::retire(uint32_t slot, VkImageView* view) {
  if (*view != VK_NULL_HANDLE) slots_[slot].views.push_back(*view);
  *view = VK_NULL_HANDLE;
}

void FrameRetirement::release(uint32_t slot) {
  Retired& r = slots_[slot];
  for (GpuBuffer& b : r.buffers) objects_->destroy(&b);
  for (VkImageView v : r.views) vkDestroyImageView(objects_->device(), v, objects_->allocator());
  for (GpuImage& i : r.images) objects_->destroy(&i);
  for (VkDescriptorPool p : r.pools)
    vkDestroyDescriptorPool(objects_->device(), p, objects_->allocator());
  r = Retired();
}

void FrameRetirement::releaseAll() {
  for (uint32_t slot = 0; slot < slots_.size(); ++slot) release(slot);
}

}  // namespace si::vk::detail
