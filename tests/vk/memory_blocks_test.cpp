// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The Vulkan back-end's device memory in blocks (src/vk/memory_blocks.h), on the example host's
// device (lavapipe without a GPU): many small buffers share one block, each range aligned and
// its mapped bytes its own; buffers and images keep to blocks of their own; a resource past a
// quarter of a block has its own; freed ranges merge, and a block left empty is freed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "vk/device_objects.h"
#include "vulkan_host/headless_vulkan.h"

namespace si::vk::detail {
namespace {

TEST(VulkanMemoryBlocks, ResourcesShareBlocksAndEmptyBlocksAreFreed) {
  examples::HeadlessVulkan host;
  const Status created = host.create(16, 16);
  if (!created.isOk()) {
    if (std::getenv("SI_REQUIRE_VULKAN") != nullptr) FAIL() << created.toString();
    GTEST_SKIP() << created.toString();
  }
  DeviceObjects objects;
  objects.init(host.physicalDevice(), host.device(), nullptr);
  // 200 mapped buffers of 3000 bytes: one block, each range aligned, their bytes apart.
  std::vector<GpuBuffer> small(200);
  for (size_t k = 0; k < small.size(); ++k) {
    ASSERT_TRUE(
        objects.createBuffer(3000, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "small", &small[k])
            .isOk());
    ASSERT_NE(small[k].mapped, nullptr);
    std::memset(small[k].mapped, int(k), 3000);
  }
  EXPECT_EQ(objects.blocks().blockCount(), 1u);
  for (size_t k = 0; k < small.size(); ++k) {
    const uint8_t* bytes = static_cast<const uint8_t*>(small[k].mapped);
    EXPECT_EQ(bytes[0], uint8_t(k));
    EXPECT_EQ(bytes[2999], uint8_t(k)) << "buffer " << k << " was overwritten";
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(host.device(), small[k].buffer, &req);
    EXPECT_EQ(small[k].memory.offset % req.alignment, 0u);
  }
  // An image keeps to a block of its own kind; a resource past a quarter of a block gets its own.
  GpuImage image;
  ASSERT_TRUE(
      objects.createImage(64, 64, 1, 1, VK_FORMAT_R8G8B8A8_UNORM, false, "image", &image).isOk());
  EXPECT_EQ(objects.blocks().blockCount(), 2u);
  GpuBuffer large;
  ASSERT_TRUE(objects
                  .createBuffer(DeviceObjects::kBlockBytes / 2, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                false, "large", &large)
                  .isOk());
  EXPECT_EQ(objects.blocks().blockCount(), 3u);
  objects.destroy(&large);
  EXPECT_EQ(objects.blocks().blockCount(), 2u);
  // Every other small buffer freed, then the rest: the holes merge and the block is freed; a
  // new buffer fits where the freed ones were.
  for (size_t k = 0; k < small.size(); k += 2) objects.destroy(&small[k]);
  EXPECT_EQ(objects.blocks().blockCount(), 2u);
  GpuBuffer again;
  ASSERT_TRUE(
      objects.createBuffer(3000, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "again", &again).isOk());
  EXPECT_EQ(objects.blocks().blockCount(), 2u);
  objects.destroy(&again);
  for (size_t k = 1; k < small.size(); k += 2) objects.destroy(&small[k]);
  EXPECT_EQ(objects.blocks().blockCount(), 1u) << "the buffers' block is freed";
  objects.destroy(&image);
  EXPECT_EQ(objects.blocks().blockCount(), 0u);
  objects.release();
  EXPECT_TRUE(host.messages().empty());
}

}  // namespace
}  // namespace si::vk::detail
