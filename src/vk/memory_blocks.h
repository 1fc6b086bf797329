// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The back-end's device memory: a few large blocks per memory type, each resource a range of
// one, instead of a vkAllocateMemory per buffer and image (drivers allow as few as 4,096
// allocations, and engines count them). Buffers and images keep to blocks of their own (no
// bufferImageGranularity to mind); a resource larger than a quarter of a block gets a block of
// its own. Host-visible blocks stay mapped whole. Freed ranges merge with their free
// neighbours; a block with nothing left in it is freed.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <map>
#include <vector>

#include "si/core/status.h"

namespace si::vk::detail {

/// A range of a block: where a resource is bound.
struct MemoryRange {
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  VkDeviceSize size = 0;
  void* mapped = nullptr;  ///< Host-visible blocks: the range's first byte.
  uint32_t block = 0;      ///< The block's index (MemoryBlocks::free).
};

class MemoryBlocks {
 public:
  /// Blocks of `block_bytes` (a power of two not required) on `device`.
  void init(VkDevice device, const VkAllocationCallbacks* allocator,
            const VkPhysicalDeviceMemoryProperties& memory, VkDeviceSize block_bytes);
  /// A range for `req` in memory with `flags` (mapped when host-visible), among buffers
  /// (`linear`) or images. kBackend naming the failed call or the missing memory type.
  Status allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags flags, bool linear,
                  const char* what, MemoryRange* out);
  /// Gives `range` back (a null range is nothing).
  void free(const MemoryRange& range);
  /// Frees every block (the resources bound to them destroyed first).
  void release();
  /// Blocks allocated now, and their bytes.
  size_t blockCount() const;
  VkDeviceSize blockBytes() const;

 private:
  struct Block {
    VkDeviceMemory memory = VK_NULL_HANDLE;  ///< Null: freed (its index reused).
    uint32_t type = 0;
    bool linear = false;
    VkDeviceSize size = 0;
    void* mapped = nullptr;
    std::map<VkDeviceSize, VkDeviceSize> free;  ///< Offset -> size of each free run.
  };
  // A range of `req` from `b`'s free runs (first fit); false when none holds it.
  static bool carve(Block* b, const VkMemoryRequirements& req, VkDeviceSize* offset);

  VkDevice device_ = VK_NULL_HANDLE;
  const VkAllocationCallbacks* allocator_ = nullptr;
  VkPhysicalDeviceMemoryProperties memory_{};
  VkDeviceSize block_bytes_ = 0;
  std::vector<Block> blocks_;
};

}  // namespace si::vk::detail
