// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The Vulkan GPU-driven path's crowds: per (character, crowd) the crowd's state as the cull
// passes read it (its instances, clips, frame times, the character's bucket ranges and
// pre-skinning lists, the entry indices the draws read), shared by every view of the crowd, and
// kept up to date by copies from a staging buffer of the frame slot recorded before the passes:
// the whole state when the crowd, its shape or its size outgrew the buffers, else only the
// instances that changed since (CrowdExport::changedSince).

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "crowd/layer_compose_table.h"
#include "si/core/status.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/gpu_crowd_state.h"
#include "si/crowd/handle_pool.h"
#include "vk/character_resources.h"
#include "vk/device_objects.h"
#include "vk/frame_slots.h"

namespace si::vk::detail {

/// One buffer to make: where it goes, its bytes and usage, and what it is (for errors).
struct BufferNeed {
  GpuBuffer* buffer;
  uint64_t bytes;
  VkBufferUsageFlags usage;
  const char* what;
};

/// Makes each of `needs` (device-local) for `instances` instances. kLimitExceeded naming the
/// first past `max_range` (maxStorageBufferRange; nothing made then); kBackend on a failed call
/// (what was made stays in place, for the caller to retire).
Status createBuffers(DeviceObjects* objects, Span<const BufferNeed> needs, VkDeviceSize max_range,
                     uint64_t instances);

/// One crowd's state on the GPU, for one character.
struct DrivenCrowd {
  uint64_t version = 0;     ///< CrowdExport::stateVersion() uploaded.
  uint64_t generation = 0;  ///< Counts the buffers' re-creations (a view's sets follow it).
  uint32_t instances = 0, capacity = 0, sub_meshes = 0, buckets = 0;
  /// The instances (si::GpuInstanceState), clips, frame times; per bucket its index range and
  /// its pre-skinning list (vertices, list offset, first local index, local indices; 0 vertices
  /// without a ring); the entry indices (vertex binding 1 of the draws: 0 to capacity x
  /// sub-meshes); layered animation's overlays (si::GpuOverlayState per instance, then with 2D
  /// blends each instance's two extra layers from index `capacity`), layer mask table
  /// (si::layerMaskTable) and compose table (2D blends: si::detail::layerComposeTable), 16-byte
  /// placeholders without.
  GpuBuffer state, clips, times, ranges, bucket_info, identity, overlays, masks, compose_table;
  std::vector<GpuBuffer> staging;  ///< One per frame slot.
  /// Its device buffers (the staging aside).
  template <typename Self>
  static auto bufferList(Self& d) {
    return std::array{&d.state,    &d.clips,    &d.times, &d.ranges,       &d.bucket_info,
                      &d.identity, &d.overlays, &d.masks, &d.compose_table};
  }
  std::array<GpuBuffer*, 9> buffers() { return bufferList(*this); }
  std::array<const GpuBuffer*, 9> buffers() const { return bufferList(*this); }
  /// Layered animation: some instance holds an overlay (CrowdExport::playsOverlays; the views'
  /// passes write layer records), and the mask table uploaded. 2D blends
  /// (CrowdExport::writesExtraLayers): the extra layers are uploaded and the layers composed
  /// (the compose table uploaded, and its shape).
  bool layers = false, extras = false;
  std::vector<int32_t> mask_table, compose_values;
  si::detail::ComposeShape shape;
  uint64_t used = 0;               ///< The renderer's frame of its last update.
  /// Motion vectors: the crowd's frames (a step of its clock since the last passes starts one),
  /// the step count they were counted at, and the handle slots its instances use.
  uint64_t frame = 0, frame_steps = 0;
  uint32_t slots_needed = 1;
};

/// What the last update uploaded: bytes of instance state, and copy regions.
struct CrowdUpload {
  uint64_t state_bytes = 0;
  uint32_t regions = 0;
  bool whole = false;
};

class GpuDrivenCrowds {
 public:
  /// `pre_skin`: the views have rings (the bucket info names each bucket's list).
  void init(DeviceObjects* objects, FrameRetirement* retirement, VkDeviceSize max_storage_range,
            uint32_t frames_in_flight, bool pre_skin);
  /// Records into `cmd` (outside rendering, frame slot `slot`) the copies that bring
  /// (`character`, `crowd`)'s state up to date, creating or re-creating its buffers as it
  /// grows; `*out` is then the crowd's. kLimitExceeded when a buffer passes
  /// maxStorageBufferRange; kBackend on a failed call.
  Status update(VkCommandBuffer cmd, uint32_t slot, uint32_t character, const CharacterResources& c,
                const CrowdManager& crowd, DrivenCrowd** out, CrowdUpload* upload);
  /// Retires (into slot `slot`) every crowd last updated before frame `before` that no view
  /// keeps (`kept`: the crowds views hold).
  void evict(uint32_t slot, uint64_t before, const std::vector<const DrivenCrowd*>& kept);
  /// Retires (into slot `slot`) every crowd updated at frame `frame` (a frame thrown away: its
  /// copies never ran) and lists them in `*forgotten`.
  void forgetUpdatedAt(uint32_t slot, uint64_t frame, std::vector<const DrivenCrowd*>* forgotten);
  /// Marks `d` used at frame `frame`.
  static void touch(DrivenCrowd* d, uint64_t frame) { d->used = frame; }
  /// Device bytes of the crowds' buffers.
  uint64_t deviceBytes() const;
  uint32_t size() const { return uint32_t(crowds_.size()); }
  /// Destroys everything (the host has waited for the device).
  void release();

 private:
  // What a crowd's layered animation needs of its buffers.
  struct LayerNeeds {
    bool layers = false, extras = false;
    uint64_t mask_bytes = 0, compose_bytes = 0;
  };
  Status reshape(DrivenCrowd* d, uint32_t slot, uint32_t n, uint32_t sub_meshes, uint32_t buckets,
                 uint32_t clips, uint32_t times, const LayerNeeds& layering);
  void retire(uint32_t slot, DrivenCrowd* d);

  DeviceObjects* objects_ = nullptr;
  FrameRetirement* retirement_ = nullptr;
  VkDeviceSize max_storage_range_ = 0;
  uint32_t frames_in_flight_ = 1;
  bool pre_skin_ = false;
  std::map<std::pair<uint32_t, uint64_t>, DrivenCrowd> crowds_;  // (character, crowd identity)
  std::vector<DenseRange> changed_;                              // update()'s, kept between frames.
};

}  // namespace si::vk::detail
