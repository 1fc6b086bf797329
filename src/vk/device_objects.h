// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The Vulkan objects the back-end creates on the host's device: buffers and images, each with
// memory of its own (one allocation per object: a first back-end's allocator), through the
// host's allocation callbacks; and Vulkan results as named Statuses.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "si/core/status.h"
#include "vk/memory_blocks.h"

namespace si::vk::detail {

/// A Vulkan structure of type `T`, zeroed, with its sType.
template <typename T>
T vkStruct(VkStructureType type) {
  T v{};
  v.sType = type;
  return v;
}

/// `v` rounded up to a multiple of `a`.
inline VkDeviceSize alignUp(VkDeviceSize v, VkDeviceSize a) {
  return (v + a - 1) / a * a;
}

/// Ok for VK_SUCCESS; kBackend naming `call` and the result otherwise.
Status checkVk(VkResult result, const char* call);

/// A descriptor set layout of `bindings` and a pipeline layout of that one set. kBackend naming
/// the failed call (what was made is in the outputs either way).
Status createSetLayouts(VkDevice device, const VkAllocationCallbacks* allocator,
                        const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                        VkDescriptorSetLayout* set_layout, VkPipelineLayout* pipeline_layout);
/// A descriptor pool for `count` sets of `layout` (of `bindings`) and those sets (into
/// `sets[0..count)`). kBackend naming the failed call (the pool made is in `*pool` either way).
Status createDescriptorSets(VkDevice device, const VkAllocationCallbacks* allocator,
                            VkDescriptorSetLayout layout,
                            const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                            uint32_t count, VkDescriptorPool* pool, VkDescriptorSet* sets);
/// A descriptor pool for one set of each of `layouts` (whose bindings, all together, are
/// `bindings`) and those sets (into `sets[0..layouts.size())`). The same errors.
Status createDescriptorSets(VkDevice device, const VkAllocationCallbacks* allocator,
                            const std::vector<VkDescriptorSetLayout>& layouts,
                            const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                            VkDescriptorPool* pool, VkDescriptorSet* sets);
/// The same for one set.
inline Status createDescriptorSet(VkDevice device, const VkAllocationCallbacks* allocator,
                                  VkDescriptorSetLayout layout,
                                  const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                                  VkDescriptorPool* pool, VkDescriptorSet* set) {
  return createDescriptorSets(device, allocator, layout, bindings, 1, pool, set);
}

struct GpuBuffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  MemoryRange memory;  ///< Its range of a block (memory_blocks.h).
  VkDeviceSize size = 0;
  void* mapped = nullptr;  ///< Host-visible buffers stay mapped.
};

struct GpuImage {
  VkImage image = VK_NULL_HANDLE;
  MemoryRange memory;
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  uint32_t width = 0, height = 0, layers = 1, levels = 1;
};

/// The host's device and what creating on it needs: buffers and images bound to ranges of the
/// renderer's memory blocks (memory_blocks.h).
class DeviceObjects {
 public:
  /// Memory blocks of 64 MiB.
  static constexpr VkDeviceSize kBlockBytes = VkDeviceSize(64) << 20;

  void init(VkPhysicalDevice physical, VkDevice device, const VkAllocationCallbacks* allocator);
  /// Frees the memory blocks (every buffer and image destroyed first).
  void release() { blocks_.release(); }
  const MemoryBlocks& blocks() const { return blocks_; }
  VkDevice device() const { return device_; }
  const VkAllocationCallbacks* allocator() const { return allocator_; }

  /// A buffer of `size` bytes for `usage`: host-visible and coherent (mapped) with
  /// `host_visible`, device-local otherwise. kBackend naming the failed call, or the memory
  /// type missing; nothing kept then.
  Status createBuffer(VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible,
                      const char* what, GpuBuffer* out);
  /// A device-local 2D image of `layers` layers and `levels` levels, sampled and a transfer
  /// source and destination (and `extra_usage`), and its view of every level (2D, or 2D array
  /// when `array`; of the depth aspect for a depth format without stencil).
  Status createImage(uint32_t width, uint32_t height, uint32_t layers, uint32_t levels,
                     VkFormat format, bool array, const char* what, GpuImage* out,
                     VkImageUsageFlags extra_usage = 0);
  void destroy(GpuBuffer* b);
  void destroy(GpuImage* i);

 private:
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  const VkAllocationCallbacks* allocator_ = nullptr;
  VkPhysicalDeviceMemoryProperties memory_{};
  MemoryBlocks blocks_;
};

}  // namespace si::vk::detail
