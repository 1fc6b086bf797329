// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The Vulkan back-end's GPU-driven path: per (character, view), the cull, commands, scatter and
// pre-skinning passes' output, recorded as si::gl's GpuCulledPath runs them (the same SPIR-V of
// the same shaders: the selection is cull_math.h's) over the crowd's state (gpu_driven_crowds.h,
// shared by the crowd's views), then the indexed indirect draws of every (LOD, sub-mesh) bucket.
// What a frame slot's earlier frame may still read is destroyed only when the slot comes round
// again (beginFrame). With occlusion culling the passes run twice: the first phase before the
// host's first rendering, the depth pyramid (depth_pyramid.h) and the second phase after it.
// Impostors: the impostor quads pass after the scatter pass, the impostor draw after the meshes'
// (gpu_driven_impostors.cpp). Layered animation: the cull pass writes each visible instance's
// layer record beside its record, the pre-skinning pass and the draws compose the overlay on its
// mask per vertex (the layered programs); with 2D blends the layer compose pass composes each
// visible instance's masked rows after the scatter pass, and the skinning reads them (the
// composed programs). What is not built yet (live poses) is refused by the renderer.

#include <vulkan/vulkan.h>

#include <array>
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
#include "vk/depth_pyramid.h"
#include "vk/device_objects.h"
#include "vk/frame_slots.h"
#include "vk/gpu_driven_crowds.h"
#include "vk/gpu_driven_layout.h"
#include "vk/impostor_passes.h"
#include "vk/program_modules.h"
#include "vk/skinned_pipeline.h"

namespace si::vk::detail {

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
  const GpuImage* no_pyramid = nullptr;  ///< Bound as the depth pyramid without occlusion.
  const PyramidPasses* pyramid_passes = nullptr;
  const ImpostorPasses* impostors = nullptr;  ///< The impostor quads pass and draws.
  uint32_t max_image_size = 4096;  ///< maxImageDimension2D.
  uint32_t max_groups_x = 65535, max_groups_y = 65535;
  VkDeviceSize max_storage_range = 0;  ///< maxStorageBufferRange.
  uint32_t frames_in_flight = 1;
  /// Bytes of each view's ring of pre-skinned vertices (RendererDesc::gpu_driven_ring_bytes);
  /// 0: every instance skinned in the vertex stage.
  uint64_t ring_bytes = 0;
  /// beginFrame() calls a view (or a crowd no view keeps) stays unused before it is freed
  /// (RendererDesc::gpu_driven_idle_frames); 0: never.
  uint32_t idle_frames = 0;
  /// Motion vectors (RendererDesc::motion_format): every view's passes also write each visible
  /// instance's previous record, and its shaded draws the motion.
  bool motion = false;
  /// Every draw single-sampled (RendererDesc::samples and depth_only_samples 1): the impostor
  /// quads pass leaves out the quads that cover no pixel centre.
  bool single_sampled = true;
  /// The renderer's programs (vulkanPrograms() order): the characters' draws' and pre-skinning
  /// passes' default blocks.
  const std::vector<ProgramModules>* programs = nullptr;
};

class GpuDrivenViews {
 public:
  void init(const DrivenShared& shared);
  /// Frame slot `slot` begins: what it retired when it last ran is destroyed.
  void beginFrame(uint32_t slot);
  /// Records `view`'s passes for character `character` (`c`) with `camera` into `cmd` (outside
  /// rendering), in frame slot `slot`, the passes' uniforms in `region`: occlusion culling's
  /// first phase with `occlusion`.
  Status recordPasses(VkCommandBuffer cmd, uint32_t slot, FrameRegion region, uint32_t character,
                      const CharacterResources& c, const CrowdView& view, const Camera& camera,
                      bool occlusion);
  /// Records occlusion culling's second phase of `view`'s passes of this frame (a first phase):
  /// `depth` into the view's pyramid, then the passes again, testing against it.
  Status recordOcclusion(VkCommandBuffer cmd, uint32_t slot, FrameRegion region, uint32_t character,
                         const CharacterResources& c, const CrowdView& view,
                         const DepthSource& depth);
  /// Records the draws of `view`'s passes of this frame into `cmd` (inside rendering), shaded or
  /// depth only as `target` says: the pre-skinned entries pulled from the ring, then the others
  /// skinned in the vertex stage.
  Status recordDraw(VkCommandBuffer cmd, FrameRegion region, uint32_t character,
                    const CharacterResources& c, const CrowdView& view, const DrawTarget& target,
                    const glm::vec3& light_direction, DrawStats* stats);
  /// The host threw away what was recorded in frame slot `slot` since its beginFrame(): the views
  /// whose passes it recorded, the crowds it updated and the views of those crowds are
  /// forgotten (their next passes start over), what they had destroyed once every slot has
  /// begun again.
  void discardFrame(uint32_t slot);
  /// The crowds' and views' device memory.
  GpuDrivenMemory memory() const;
  /// What `view`'s last passes of `character` (`c`) counted (from their slot's readback).
  /// kInvalidArgument when it has none.
  Status readCounts(uint32_t character, const CharacterResources& c, const CrowdView& view,
                    GpuDrivenCounts* out) const;
  /// What the last recordPasses() uploaded of its crowd's state.
  const CrowdUpload& lastUpload() const { return last_upload_; }
  /// Destroys everything (the host has waited for the device).
  void release();

 private:
  struct View {
    const DrivenCrowd* crowd = nullptr;  // The crowd state its sets were written for,
    uint64_t generation = 0;             // at this generation of its buffers.
    uint32_t capacity = 0, sub_meshes = 0, buckets = 0;
    // The view's LODs; the passes' counters, records, visible list, entries and indirect
    // commands; pre-skinning's entry data, ring and tangent ring (the ring stands in without);
    // motion vectors' previous records and previous positions' ring (16 bytes without); layered
    // animation's layer records and previous layer records (16 bytes without), and with composed
    // layers (2D blends) the rows the compose pass writes, and the previous ones.
    GpuBuffer lods, counters, records, visible, entries, commands;
    GpuBuffer entry_data, ring, tangent_ring, previous, previous_ring, layers, previous_layers;
    GpuBuffer rows, previous_rows;
    // Its device buffers sized by the crowd (the staging, readback and drawn records aside).
    template <typename Self>
    static auto bufferList(Self& v) {
      return std::array{&v.lods,
                        &v.counters,
                        &v.records,
                        &v.visible,
                        &v.entries,
                        &v.commands,
                        &v.entry_data,
                        &v.ring,
                        &v.tangent_ring,
                        &v.previous,
                        &v.previous_ring,
                        &v.layers,
                        &v.previous_layers,
                        &v.rows,
                        &v.previous_rows};
    }
    std::array<GpuBuffer*, 15> buffers() { return bufferList(*this); }
    std::array<const GpuBuffer*, 15> buffers() const { return bufferList(*this); }
    // Motion vectors: the records the passes drew per handle slot, two parities (the frame's,
    // the previous one's), kept across reshapes; the crowd frame of the view's last passes and
    // of its last camera, whether that camera was the previous frame's, and both cameras.
    GpuBuffer drawn;
    uint32_t drawn_slots = 0;
    uint64_t motion_frame = 0, camera_frame = 0;
    bool previous_known = false;
    glm::dvec3 position{0.0}, previous_position{0.0};
    glm::mat4 view_projection{1.0f}, previous_view_projection{1.0f};
    uint32_t ring_vertices = 0;      // 0: no pre-skinning.
    // How the last passes skinned the crowd's layers (and, composed, the compose pass's groups).
    Layering layering = kNoLayers;
    uint32_t compose_groups_x = 1, compose_groups_y = 1;
    std::vector<GpuBuffer> staging;  // Per frame slot: the LODs' seed.
    // Impostors (the crowd's impostor level, 0: none): the quads the impostor quads pass writes,
    // its set and the impostor draw's (for the atlas's clip table `impostor_clips`).
    uint32_t impostor_lod = 0;
    GpuBuffer quads;
    VkDescriptorPool impostor_pool = VK_NULL_HANDLE;
    VkDescriptorSet impostor_sets[2] = {};  // The quads pass's, the draw's.
    VkBuffer impostor_clips = VK_NULL_HANDLE;
    // Per frame slot: the counters after its passes (each phase's, with occlusion culling).
    std::vector<GpuBuffer> readback;
    bool counted = false;  // Passes were recorded: readback[passes_slot] holds them,
    uint32_t phases = 1;   // of this many phases.
    // The last passes: their uniforms (the cull, commands, scatter, pre-skinning, impostor quads
    // and layer compose passes', in the frame's region), the cull pass's groups, and occlusion
    // culling's phase (0: none; 1: the first, awaiting recordOcclusion; 2: the second).
    VkDeviceSize defaults_at[6] = {};
    uint32_t groups_x = 1, groups_y = 1;
    uint32_t phase = 0;
    // Occlusion culling: the depth pyramid, and the passes' set of each frame slot with it
    // bound (written at each second phase: the pyramid is remade when the depth's size changes).
    DepthPyramid pyramid;
    VkDescriptorPool occlusion_pool = VK_NULL_HANDLE;
    std::vector<VkDescriptorSet> occlusion_sets;
    // The passes' set and the draw's, each in a pool of its own.
    VkDescriptorPool pass_pool = VK_NULL_HANDLE, draw_pool = VK_NULL_HANDLE;
    VkDescriptorSet pass_set = VK_NULL_HANDLE, draw_set = VK_NULL_HANDLE;
    Camera camera;                 // The last passes'.
    bool passes_recorded = false;  // In this frame slot's frame, since beginFrame.
    uint32_t passes_slot = 0;
    uint64_t used = 0;  // frame_ of its last passes.
  };
  // Makes `v`'s buffers for crowd state `d` and its sets (what it had is retired into slot
  // `slot`), and records its LODs' seed (the CPU view's, CrowdExport::lods) into `cmd`.
  Status reshape(VkCommandBuffer cmd, View* v, uint32_t slot, const CharacterResources& c,
                 const DrivenCrowd& d, const CrowdView& view);
  void retire(uint32_t slot, View* v);
  // An execution dependency: what the draws and passes recorded before read of the passes'
  // buffers (and the pyramid) is read before the copies and passes that follow write them.
  static void recordReadsBeforeRewrites(VkCommandBuffer cmd);
  // Motion vectors: drawn records for `slots` handle slots (grown to twice the last within
  // maxStorageBufferRange, zeroed in `cmd`; the old retired into `slot`; `*remade` when they
  // were). kLimitExceeded past maxStorageBufferRange.
  Status ensureDrawn(VkCommandBuffer cmd, uint32_t slot, View* v, uint32_t slots, bool* remade);
  // Motion vectors: `v`'s cameras for passes with `camera` in crowd frame `frame` (the last
  // frame's camera is the previous one when it was the frame before).
  static void updateMotionCameras(View* v, uint64_t frame, const Camera& camera);
  // Writes every binding of the passes' set `set` for `v`, character `c` and crowd state `d`,
  // the depth pyramid `pyramid` (layout `pyramid_layout`).
  void writePassSet(VkDescriptorSet set, View* v, const CharacterResources& c, const DrivenCrowd& d,
                    VkImageView pyramid, VkImageLayout pyramid_layout);
  // Records the passes of `v` with set `set` into `cmd` (the crowd's state and the view's LODs
  // are up to date), their counters copied into slot `slot`'s readback at phase `phase_index`.
  Status recordCullPasses(VkCommandBuffer cmd, View* v, VkDescriptorSet set, uint32_t slot,
                          uint32_t phase_index, const CharacterResources& c);
  // Impostors: `v`'s quads (one per instance) and its sets for `c`'s atlas, made when missing
  // (the old retired into slot `slot`), and the quads pass's uniforms for `camera` at `block`.
  Status ensureImpostors(uint32_t slot, View* v, const CharacterResources& c);
  void writeImpostorDefaults(uint8_t* block, const View& v, const CharacterResources& c,
                             const Camera& camera) const;
  // Records the impostor quads pass of `v` (after its scatter pass).
  void recordImpostorQuads(VkCommandBuffer cmd, const View& v) const;
  // Records `v`'s impostor draw (inside rendering, after its meshes').
  Status recordImpostorDraw(VkCommandBuffer cmd, FrameRegion region, const View& v,
                            const CharacterResources& c, bool depth_only,
                            const glm::vec3& light_direction) const;
  // Retires all of the view at `it` (its staging and readback too) and forgets it.
  void forget(uint32_t slot, std::map<std::pair<uint32_t, uint64_t>, View>::iterator it);

  DrivenShared shared_;
  std::map<std::pair<uint32_t, uint64_t>, View> views_;  // By (character, view identity).
  // Frees the views unused for shared_.idle_frames frames (into slot `slot`), then the crowds
  // no view keeps that are as old.
  void evictIdle(uint32_t slot);

  uint64_t frame_ = 0;  // beginFrame() calls.
  FrameRetirement retirement_;
  GpuDrivenCrowds crowds_;
  CrowdUpload last_upload_;
};

}  // namespace si::vk::detail
