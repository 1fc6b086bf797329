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

void FrameRetirement::destroy(Retired* retired) {
  Retired& r = *retired;
  for (GpuBuffer& b : r.buffers) objects_->destroy(&b);
  for (VkImageView v : r.views) vkDestroyImageView(objects_->device(), v, objects_->allocator());
  for (GpuImage& i : r.images) objects_->destroy(&i);
  for (VkDescriptorPool p : r.pools)
    vkDestroyDescriptorPool(objects_->device(), p, objects_->allocator());
  r = Retired();
}

void FrameRetirement::holdForCycle(uint32_t slot, uint32_t slots) {
  Held h;
  h.retired = std::move(slots_[slot]);
  slots_[slot] = Retired();
  h.waiting = slots >= 32 ? 0xFFFFFFFFu : (1u << slots) - 1u;
  held_.push_back(std::move(h));
}

void FrameRetirement::release(uint32_t slot) {
  destroy(&slots_[slot]);
  for (auto it = held_.begin(); it != held_.end();) {
    it->waiting &= ~(1u << slot);
    if (it->waiting != 0) {
      ++it;
      continue;
    }
    destroy(&it->retired);
    it = held_.erase(it);
  }
}

void FrameRetirement::releaseAll() {
  for (uint32_t slot = 0; slot < slots_.size(); ++slot) destroy(&slots_[slot]);
  for (Held& h : held_) destroy(&h.retired);
  held_.clear();
}

}  // namespace si::vk::detail
