// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The back-end's device memory in blocks.
#include "vk/memory_blocks.h"

#include <algorithm>
#include <iterator>

#include "core/str_cat.h"
#include "vk/device_objects.h"

namespace si::vk::detail {

using si::detail::strCat;

void MemoryBlocks::init(VkDevice device, const VkAllocationCallbacks* allocator,
                        const VkPhysicalDeviceMemoryProperties& memory, VkDeviceSize block_bytes) {
  release();
  device_ = device;
  allocator_ = allocator;
  memory_ = memory;
  block_bytes_ = block_bytes;
}

bool MemoryBlocks::carve(Block* b, const VkMemoryRequirements& req, VkDeviceSize* offset) {
  const VkDeviceSize alignment = std::max<VkDeviceSize>(req.alignment, 1);
  for (auto it = b->free.begin(); it != b->free.end(); ++it) {
    const VkDeviceSize start = it->first, end = it->first + it->second;
    const VkDeviceSize at = alignUp(start, alignment);
    if (at > end || end - at < req.size) continue;
    b->free.erase(it);
    if (at > start) b->free.emplace(start, at - start);
    if (end > at + req.size) b->free.emplace(at + req.size, end - (at + req.size));
    *offset = at;
    return true;
  }
  return false;
}

Status MemoryBlocks::allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags flags,
                              bool linear, const char* what, MemoryRange* out) {
  // The first memory type the resource may use that has `flags`.
  uint32_t type = UINT32_MAX;
  for (uint32_t t = 0; t < memory_.memoryTypeCount && type == UINT32_MAX; ++t)
    if ((req.memoryTypeBits & (1u << t)) != 0 &&
        (memory_.memoryTypes[t].propertyFlags & flags) == flags)
      type = t;
  if (type == UINT32_MAX)
    return {StatusCode::kBackend, strCat(what, ": the device has no memory type for it")};
  const bool own_block = req.size > block_bytes_ / 4;
  VkDeviceSize offset = 0;
  for (uint32_t k = 0; k < blocks_.size() && !own_block; ++k) {
    Block& b = blocks_[k];
    if (b.memory == VK_NULL_HANDLE || b.type != type || b.linear != linear) continue;
    if (!carve(&b, req, &offset)) continue;
    *out = {b.memory, offset, req.size,
            b.mapped != nullptr ? static_cast<uint8_t*>(b.mapped) + offset : nullptr, k};
    return Status::ok();
  }
  // A new block (or the resource's own), in the first freed slot.
  Block b;
  b.type = type;
  b.linear = linear;
  b.size = own_block ? req.size : block_bytes_;
  auto info = vkStruct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  info.allocationSize = b.size;
  info.memoryTypeIndex = type;
  Status s = checkVk(vkAllocateMemory(device_, &info, allocator_, &b.memory),
                     strCat("vkAllocateMemory (", what, ")").c_str());
  if (s.isOk() && (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0)
    s = checkVk(vkMapMemory(device_, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped), "vkMapMemory");
  if (!s.isOk()) {
    if (b.memory != VK_NULL_HANDLE) vkFreeMemory(device_, b.memory, allocator_);
    return s;
  }
  b.free.emplace(0, b.size);
  carve(&b, req, &offset);  // At 0: a new block holds it.
  uint32_t index = 0;
  while (index < blocks_.size() && blocks_[index].memory != VK_NULL_HANDLE) ++index;
  if (index == blocks_.size()) blocks_.emplace_back();
  blocks_[index] = std::move(b);
  const Block& placed = blocks_[index];
  *out = {placed.memory, offset, req.size,
          placed.mapped != nullptr ? static_cast<uint8_t*>(placed.mapped) + offset : nullptr,
          index};
  return Status::ok();
}

void MemoryBlocks::free(const MemoryRange& range) {
  if (range.memory == VK_NULL_HANDLE || range.block >= blocks_.size()) return;
  Block& b = blocks_[range.block];
  if (b.memory != range.memory) return;
  // Back into the free runs, merged with the runs just before and after it.
  VkDeviceSize start = range.offset, end = range.offset + range.size;
  auto next = b.free.lower_bound(start);
  if (next != b.free.end() && next->first == end) {
    end += next->second;
    next = b.free.erase(next);
  }
  if (next != b.free.begin()) {
    auto previous = std::prev(next);
    if (previous->first + previous->second == start) {
      start = previous->first;
      b.free.erase(previous);
    }
  }
  b.free.emplace(start, end - start);
  if (b.free.size() == 1 && b.free.begin()->first == 0 && b.free.begin()->second == b.size) {
    vkFreeMemory(device_, b.memory, allocator_);  // Unmapped with it.
    b = Block();
  }
}

void MemoryBlocks::release() {
  for (Block& b : blocks_)
    if (b.memory != VK_NULL_HANDLE) vkFreeMemory(device_, b.memory, allocator_);
  blocks_.clear();
}

size_t MemoryBlocks::blockCount() const {
  return size_t(std::count_if(blocks_.begin(), blocks_.end(),
                              [](const Block& b) { return b.memory != VK_NULL_HANDLE; }));
}

VkDeviceSize MemoryBlocks::blockBytes() const {
  VkDeviceSize n = 0;
  for (const Block& b : blocks_) n += b.memory != VK_NULL_HANDLE ? b.size : 0;
  return n;
}

}  // namespace si::vk::detail
