// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The Vulkan back-end's GPU-driven path: per (character, view), the crowd's state on the GPU and
// the cull, commands and scatter passes' output, recorded as si::gl's GpuCulledPath runs them
// (the same SPIR-V of the same shaders: the selection is cull_math.h's), then one indexed
// indirect draw of every (LOD, sub-mesh) bucket. The state is copied in from a staging buffer of
// the frame slot when the crowd changed; what a frame slot's earlier frame may still read is
// destroyed only when the slot comes round again (beginFrame). What is not built yet (layers,
// motion vectors, live poses, impostors, occlusion, pre-skinning) is refused by the renderer.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "si/core/status.h"
#include "si/crowd/camera.h"
#include "si/crowd/crowd_view.h"
#include "si/vk/renderer.h"
#include "vk/character_resources.h"
#include "vk/character_set.h"
#include "vk/device_objects.h"
#include "vk/gpu_driven_layout.h"
#include "vk/program_modules.h"
#include "vk/skinned_pipeline.h"

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

/// What the views share of the renderer's, set once.
struct DrivenShared {
  DeviceObjects* objects = nullptr;
  const ComputeLayout* compute_layout = nullptr;
  /// The cull, commands and scatter passes' pipelines and modules (their default blocks).
  VkPipeline passes[3] = {};
  const ProgramModules* pass_modules[3] = {};
  const SkinnedLayout* draw_layout = nullptr;  ///< The GPU-driven draw programs' set layout.
  const GpuBuffer* ring = nullptr;
  VkSampler nearest = VK_NULL_HANDLE, linear = VK_NULL_HANDLE;
  const GpuImage* custom = nullptr;
  const GpuImage* no_morphs = nullptr;
  const GpuBuffer* unbuilt = nullptr;    ///< Bound where the passes read or write nothing.
  const GpuImage* no_pyramid = nullptr;  ///< Bound as the depth pyramid.
  uint32_t max_groups_x = 65535, max_groups_y = 65535;
  VkDeviceSize max_storage_range = 0;  ///< maxStorageBufferRange.
  uint32_t frames_in_flight = 1;
  /// Bytes of each view's ring of pre-skinned vertices (RendererDesc::gpu_driven_ring_bytes);
  /// 0: every instance skinned in the vertex stage.
  uint64_t ring_bytes = 0;
  /// The renderer's programs (vulkanPrograms() order): the characters' draws' and pre-skinning
  /// passes' default blocks.
  const std::vector<ProgramModules>* programs = nullptr;
};

class GpuDrivenViews {
 public:
  void init(const DrivenShared& shared) { shared_ = shared; }
  /// Frame slot `slot` begins: what it retired when it last ran is destroyed.
  void beginFrame(uint32_t slot);
  /// Records `view`'s passes for character `character` (`c`) with `camera` into `cmd` (outside
  /// rendering), in frame slot `slot`, the passes' uniforms in `region`.
  Status recordPasses(VkCommandBuffer cmd, uint32_t slot, FrameRegion region, uint32_t character,
                      const CharacterResources& c, const CrowdView& view, const Camera& camera);
  /// Records the draws of `view`'s passes of this frame into `cmd` (inside rendering), shaded or
  /// depth only as `target` says: the pre-skinned entries pulled from the ring, then the others
  /// skinned in the vertex stage.
  Status recordDraw(VkCommandBuffer cmd, FrameRegion region, uint32_t character,
                    const CharacterResources& c, const CrowdView& view, const DrawTarget& target,
                    const glm::vec3& light_direction, DrawStats* stats);
  /// Device bytes of the views' buffers.
  uint64_t deviceBytes() const;
  /// Destroys everything (the host has waited for the device).
  void release();

 private:
  struct View {
    uint64_t crowd = 0;    // CrowdManager::identity() of the state.
    uint64_t version = 0;  // CrowdExport::stateVersion() uploaded.
    uint32_t instances = 0, capacity = 0, sub_meshes = 0, buckets = 0;
    uint32_t clip_count = 0, time_count = 0;
    // The crowd's state, clips, frame times, bucket ranges and info, the entry indices (vertex
    // binding 1); the view's LODs; the passes' counters, records, visible list, entries and
    // indirect commands.
    GpuBuffer state, clips, times, ranges, bucket_info, identity, lods;
    GpuBuffer counters, records, visible, entries, commands;
    // Pre-skinning: each pre-skinned entry's ring base and list, the ring of pre-skinned
    // vertices (16 bytes each) and of their tangents (4 bytes; the ring stands in without).
    GpuBuffer entry_data, ring, tangent_ring;
    uint32_t ring_vertices = 0;      // 0: no pre-skinning.
    std::vector<GpuBuffer> staging;  // One per frame slot.
    // The passes' set and the draw's, each in a pool of its own.
    VkDescriptorPool pass_pool = VK_NULL_HANDLE, draw_pool = VK_NULL_HANDLE;
    VkDescriptorSet pass_set = VK_NULL_HANDLE, draw_set = VK_NULL_HANDLE;
    Camera camera;                 // The last passes'.
    bool passes_recorded = false;  // In this frame slot's frame, since beginFrame.
    uint32_t passes_slot = 0;
  };
  // Makes `v`'s buffers for `n` instances of `buckets` buckets and its sets (what it had is
  // retired into slot `slot`).
  Status reshape(View* v, uint32_t slot, const CharacterResources& c, uint32_t n,
                 uint32_t sub_meshes, uint32_t buckets, uint32_t clips, uint32_t times);
  void retire(uint32_t slot, View* v);

  DrivenShared shared_;
  std::map<std::pair<uint32_t, uint64_t>, View> views_;  // By (character, view identity).
  // What each frame slot retired: destroyed when the slot begins again.
  struct Retired {
    std::vector<GpuBuffer> buffers;
    std::vector<VkDescriptorPool> pools;
  };
  std::vector<Retired> retired_ = std::vector<Retired>(8);
};

}  // namespace si::vk::detail
