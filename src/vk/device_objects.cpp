// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Buffers and images on the host's device.
#include "vk/device_objects.h"

#include "core/str_cat.h"

namespace si::vk::detail {

using si::detail::strCat;

Status checkVk(VkResult result, const char* call) {
  if (result == VK_SUCCESS) return Status::ok();
  return {StatusCode::kBackend, strCat(call, " failed: VkResult ", int(result))};
}

Status createSetLayouts(VkDevice device, const VkAllocationCallbacks* allocator,
                        const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                        VkDescriptorSetLayout* set_layout, VkPipelineLayout* pipeline_layout) {
  auto info = vkStruct<VkDescriptorSetLayoutCreateInfo>(
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  info.bindingCount = uint32_t(bindings.size());
  info.pBindings = bindings.data();
  Status s = checkVk(vkCreateDescriptorSetLayout(device, &info, allocator, set_layout),
                     "vkCreateDescriptorSetLayout");
  if (!s.isOk()) return s;
  auto pl = vkStruct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  pl.setLayoutCount = 1;
  pl.pSetLayouts = set_layout;
  return checkVk(vkCreatePipelineLayout(device, &pl, allocator, pipeline_layout),
                 "vkCreatePipelineLayout");
}

Status createDescriptorSets(VkDevice device, const VkAllocationCallbacks* allocator,
                            const std::vector<VkDescriptorSetLayout>& layouts,
                            const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                            VkDescriptorPool* pool, VkDescriptorSet* sets) {
  std::vector<VkDescriptorPoolSize> sizes;
  for (const VkDescriptorSetLayoutBinding& b : bindings) sizes.push_back({b.descriptorType, 1});
  auto pool_info =
      vkStruct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  pool_info.maxSets = uint32_t(layouts.size());
  pool_info.poolSizeCount = uint32_t(sizes.size());
  pool_info.pPoolSizes = sizes.data();
  Status s = checkVk(vkCreateDescriptorPool(device, &pool_info, allocator, pool),
                     "vkCreateDescriptorPool");
  if (!s.isOk()) return s;
  auto alloc =
      vkStruct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  alloc.descriptorPool = *pool;
  alloc.descriptorSetCount = uint32_t(layouts.size());
  alloc.pSetLayouts = layouts.data();
  return checkVk(vkAllocateDescriptorSets(device, &alloc, sets), "vkAllocateDescriptorSets");
}

Status createDescriptorSets(VkDevice device, const VkAllocationCallbacks* allocator,
                            VkDescriptorSetLayout layout,
                            const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                            uint32_t count, VkDescriptorPool* pool, VkDescriptorSet* sets) {
  std::vector<VkDescriptorSetLayoutBinding> all;
  for (uint32_t k = 0; k < count; ++k) all.insert(all.end(), bindings.begin(), bindings.end());
  return createDescriptorSets(device, allocator, std::vector<VkDescriptorSetLayout>(count, layout),
                              all, pool, sets);
}

void DeviceObjects::init(VkPhysicalDevice physical, VkDevice device,
                         const VkAllocationCallbacks* allocator) {
  physical_ = physical;
  device_ = device;
  allocator_ = allocator;
  vkGetPhysicalDeviceMemoryProperties(physical, &memory_);
  blocks_.init(device, allocator, memory_, kBlockBytes);
}

Status DeviceObjects::createBuffer(VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible,
                                   const char* what, GpuBuffer* out) {
  GpuBuffer b;
  b.size = size;
  auto info = vkStruct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  Status s = checkVk(vkCreateBuffer(device_, &info, allocator_, &b.buffer),
                     strCat("vkCreateBuffer (", what, ")").c_str());
  VkMemoryRequirements req{};
  if (s.isOk()) {
    vkGetBufferMemoryRequirements(device_, b.buffer, &req);
    s = blocks_.allocate(
        req,
        host_visible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                     : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
        true, what, &b.memory);
  }
  if (s.isOk())
    s = checkVk(vkBindBufferMemory(device_, b.buffer, b.memory.memory, b.memory.offset),
                "vkBindBufferMemory");
  if (s.isOk()) b.mapped = b.memory.mapped;
  if (!s.isOk()) {
    destroy(&b);
    return s;
  }
  *out = b;
  return s;
}

Status DeviceObjects::createImage(uint32_t width, uint32_t height, uint32_t layers, uint32_t levels,
                                  VkFormat format, bool array, const char* what, GpuImage* out,
                                  VkImageUsageFlags extra_usage) {
  GpuImage i;
  i.format = format;
  i.width = width;
  i.height = height;
  i.layers = layers;
  i.levels = levels;
  auto info = vkStruct<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = levels;
  info.arrayLayers = layers;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
               VK_IMAGE_USAGE_TRANSFER_SRC_BIT | extra_usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  Status s = checkVk(vkCreateImage(device_, &info, allocator_, &i.image),
                     strCat("vkCreateImage (", what, ")").c_str());
  if (s.isOk()) {
    VkMemoryRequirements req{};
    vkGetImageMemoryRequirements(device_, i.image, &req);
    s = blocks_.allocate(req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, false, what, &i.memory);
  }
  if (s.isOk())
    s = checkVk(vkBindImageMemory(device_, i.image, i.memory.memory, i.memory.offset),
                "vkBindImageMemory");
  if (s.isOk()) {
    auto v = vkStruct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
    v.image = i.image;
    v.viewType = array ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
    v.format = format;
    const bool depth = format == VK_FORMAT_D16_UNORM || format == VK_FORMAT_X8_D24_UNORM_PACK32 ||
                       format == VK_FORMAT_D32_SFLOAT;
    v.subresourceRange = {depth ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT)
                                : VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT),
                          0, levels, 0, layers};
    s = checkVk(vkCreateImageView(device_, &v, allocator_, &i.view),
                strCat("vkCreateImageView (", what, ")").c_str());
  }
  if (!s.isOk()) {
    destroy(&i);
    return s;
  }
  *out = i;
  return s;
}

void DeviceObjects::destroy(GpuBuffer* b) {
  if (b->buffer != VK_NULL_HANDLE) vkDestroyBuffer(device_, b->buffer, allocator_);
  blocks_.free(b->memory);
  *b = GpuBuffer{};
}

void DeviceObjects::destroy(GpuImage* i) {
  if (i->view != VK_NULL_HANDLE) vkDestroyImageView(device_, i->view, allocator_);
  if (i->image != VK_NULL_HANDLE) vkDestroyImage(device_, i->image, allocator_);
  blocks_.free(i->memory);
  *i = GpuImage{};
}

}  // namespace si::vk::detail
