// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What a frame slot holds (vk::Renderer::beginFrame): its region of the record ring, which the
// frame's draws and passes fill with records and uniforms, and what the frame retired, destroyed
// only when the slot begins again.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "si/core/status.h"
#include "vk/device_objects.h"

namespace si::vk::detail {

/// A frame slot's region of the record ring, as the renderer's draws fill it.
struct FrameRegion {
  uint8_t* mapped = nullptr;     ///< The ring's mapped bytes.
  VkDeviceSize start = 0;        ///< The slot's region in the ring.
  VkDeviceSize bytes = 0;        ///< Its size (RendererDesc::ring_bytes_per_frame).
  VkDeviceSize* used = nullptr;  ///< Its bytes filled so far this frame.
  VkDeviceSize alignment = 256;  ///< Of a dynamic uniform offset.

  /// `size` zeroed bytes after those used, aligned: their offset from the ring's start into
  /// `*at`. kLimitExceeded when the region is full (nothing taken).
  Status take(VkDeviceSize size, VkDeviceSize* at);
};

/// Buffers, images, image views and descriptor pools retired in a frame slot, destroyed when
/// the slot begins again (the host has then waited for the frame that last used them, and for
/// every frame submitted before it).
class FrameRetirement {
 public:
  void init(DeviceObjects* objects) { objects_ = objects; }
  /// Moves `*b` (when it exists) into slot `slot`'s list and empties it.
  void retire(uint32_t slot, GpuBuffer* b);
  void retire(uint32_t slot, VkDescriptorPool* pool);
  void retire(uint32_t slot, GpuImage* i);
  void retire(uint32_t slot, VkImageView* view);
  /// Moves what slot `slot` retired so far into a list destroyed only once each of the
  /// `slots` slots has begun again (release()): a thrown-away frame's, which frames of other
  /// slots still in flight may read.
  void holdForCycle(uint32_t slot, uint32_t slots);
  /// Slot `slot` begins: destroys what it retired, and what was held once every slot has begun
  /// since.
  void release(uint32_t slot);
  /// Destroys everything retired (the host has waited for the device).
  void releaseAll();

 private:
  struct Retired {
    std::vector<GpuBuffer> buffers;
    std::vector<VkDescriptorPool> pools;
    std::vector<GpuImage> images;
    std::vector<VkImageView> views;
  };
  struct Held {
    Retired retired;
    uint32_t waiting = 0;  // A bit per slot not begun since.
  };
  void destroy(Retired* r);
  DeviceObjects* objects_ = nullptr;
  std::vector<Retired> slots_ = std::vector<Retired>(8);
  std::vector<Held> held_;
};

}  // namespace si::vk::detail
