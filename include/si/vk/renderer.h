// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The Vulkan back-end (begun; issue "The crowd in a Vulkan engine"): a crowd drawn into the
/// host's own frame, on the GPU-driven path (its selection, LODs and pre-skinning computed on
/// the GPU, then indirect draws: the one for large crowds, 100k characters in 6.4 ms on an
/// H200) or the instanced path (the CPU's selection, one instanced draw per batch), from the
/// same shaders as si::Renderer's, compiled to SPIR-V at build time. A guest on the host's
/// VkDevice: it
/// creates its pipelines, buffers and images there (with the host's allocation callbacks), and
/// records into command buffers the host gives it; it never submits, waits or creates a queue.
///
/// Usage (one character, one view; the host owns instance, device, queue, targets and pacing):
/// \code
///   si::vk::Renderer crowd_renderer;
///   si::vk::RendererDesc rd;
///   rd.physical_device = gpu; rd.device = device;
///   rd.color_format = VK_FORMAT_R8G8B8A8_UNORM; rd.depth_format = VK_FORMAT_D32_SFLOAT;
///   crowd_renderer.init(rd);
///   si::vk::CharacterId id;
///   crowd_renderer.addCharacter(character, palette, &id);
///   crowd_renderer.recordUploads(cmd);          // outside rendering; submit, then when done:
///   crowd_renderer.uploadsComplete();           // its staging is freed
///   si::InstanceBatcher batcher;
///   batcher.init(crowd_renderer.batchLimits());
///   // Each frame, frame slot k (the host has waited for the GPU to finish the frame that used
///   // slot k last), inside vkCmdBeginRendering with the formats above:
///   crowd_renderer.beginFrame(k);
///   si::vk::DrawTarget target;                   // The rendering's extent, and what is drawn.
///   target.extent = extent;
///   crowd_renderer.recordDraw(cmd, target, id, crowd.view(), batcher, camera);
///   // A shadow cascade, in a rendering of depth only:
///   target.mode = si::vk::DrawMode::kDepthOnly;
///   crowd_renderer.recordDraw(cmd, target, id, cascade_view, batcher, cascade_camera);
///
///   // The GPU-driven path instead (rd.gpu_driven; the crowd only advances its clock): each
///   // view's passes before the host's renderings, then its draws inside them.
///   crowd_renderer.beginFrame(k);
///   crowd_renderer.recordGpuDrivenPasses(cmd, id, crowd.view(), camera);
///   crowd_renderer.recordGpuDrivenPasses(cmd, id, cascade_view, cascade_camera);
///   // ... vkCmdBeginRendering (depth only) ...
///   crowd_renderer.recordGpuDrivenDraw(cmd, shadow_target, id, cascade_view);
///   // ... vkCmdBeginRendering (colour and depth) ...
///   crowd_renderer.recordGpuDrivenDraw(cmd, target, id, crowd.view());
///
///   // With occlusion culling (GpuCulling::kOcclusion): the first phase (what was visible last
///   // frame) drawn, the host's depth reduced and the second phase recorded between two
///   // renderings, then the second phase's draw (the rest of what is visible).
///   crowd_renderer.recordGpuDrivenPasses(cmd, id, crowd.view(), camera, nullptr,
///                                        si::vk::GpuCulling::kOcclusion);
///   // ... vkCmdBeginRendering: the host's occluders, then ...
///   crowd_renderer.recordGpuDrivenDraw(cmd, target, id, crowd.view());
///   // ... vkCmdEndRendering; the depth to a read-only layout (a barrier to compute reads) ...
///   si::vk::DepthSource depth;
///   depth.view = depth_view; depth.extent = extent;
///   crowd_renderer.recordGpuDrivenOcclusion(cmd, id, crowd.view(), depth);
///   // ... the depth back to an attachment; vkCmdBeginRendering, loading colour and depth ...
///   crowd_renderer.recordGpuDrivenDraw(cmd, target, id, crowd.view());
/// \endcode
///
/// What is built: the vertex-shader path, shaded (the built-in material, with motion vectors
/// when asked) or depth only (shadow views, depth pre-passes), single-sampled or multisampled
/// (RendererDesc::samples), under every si::DepthConvention
/// (reverse-Z included) and with y-flipped projections; meshes of 4 or 8 influences a vertex,
/// with or without morph targets, vertex colours and a second texture coordinate set (each
/// drawn by its program variant); layered animation (overlays on their masks, 1D blends; 2D
/// blends on the GPU-driven path, through si::gl's layer compose pass);
/// palettes of every si::PaletteFormat; and the GPU-driven path's culling, LOD, pre-skinning
/// and indirect draw (recordGpuDrivenPasses, recordGpuDrivenDraw: shaded or depth only, every
/// mesh variant, with motion vectors, with two-phase occlusion culling or without, with animated
/// impostors (buildImpostor), with layered animation; not yet with live poses). Everything else
/// (the instanced path's compute pre-skinning, impostors and 2D blends, live poses, host
/// materials) is refused by name (kUnsupported).
/// What the host must do: record recordUploads() before the first draw of a character and
/// submit it before (or with) that draw; give each frame in flight its own slot (beginFrame(),
/// below RendererDesc::frames_in_flight) and wait for a slot's last frame before beginning it
/// again; submit what it recorded, or call discardFrame() (the GPU-driven passes count the
/// crowd's changes as copied once recorded). The draws test the host's depth attachment
/// (DrawTarget::depth_compare: by default VK_COMPARE_OP_LESS, VK_COMPARE_OP_GREATER for a reverse-Z
/// camera) and write it, cull back faces (counter-clockwise front faces as OpenGL draws them,
/// clockwise when the camera's projection flips the winding: Camera::flipsWinding), and flip the
/// viewport (negative height) so the image is the one OpenGL draws. They set the dynamic state they
/// use (viewport, scissor, depth compare, front face, depth bias) on each draw and leave it so; the
/// host sets its own again after them.

#include <cstdint>
#include <memory>

#include <vulkan/vulkan.h>

#include <glm/glm.hpp>

#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/core/status.h"
#include "si/crowd/camera.h"
#include "si/crowd/crowd_view.h"
#include "si/crowd/impostor_desc.h"
#include "si/crowd/instance_batcher.h"
#include "si/vk/draw_target.h"
#include "si/vk/gpu_driven.h"
#include "si/vk/renderer_desc.h"

namespace si::vk {

/// A character added to a Renderer.
struct CharacterId {
  uint32_t index = 0;
};

class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Creates the pipeline layout and the record ring on the host's device. kInvalidArgument for a
  /// missing device, a slot count outside 1..8, a morph_lod_share outside 0 to 1 or a ring
  /// smaller than one batch's records;
  /// kLimitExceeded for a ring past 4 GiB (dynamic offsets are 32-bit); kUnsupported for a device
  /// below Vulkan 1.3, without dynamic rendering, whose maxUniformBufferRange is below the
  /// 65,520 bytes of a batch's records, or that cannot render into motion_format; with motion
  /// vectors kLimitExceeded for a ring past maxStorageBufferRange; kBackend naming the Vulkan
  /// call that failed.
  Status init(const RendererDesc& desc);
  /// Destroys everything it created (the host has waited for the device's work on it).
  void shutdown();

  /// The limits to give si::InstanceBatcher::init: batches of at most 819 records, at the
  /// device's uniform buffer offset alignment.
  BatchLimits batchLimits() const;

  /// Creates `character`'s buffers and images (its vertex stream, indices, materials and
  /// `palette`, which must stay alive while it is drawn), their contents staged for
  /// recordUploads(), and its pipelines (its mesh's program variant: morph targets, 8
  /// influences, vertex words). kInvalidArgument for a palette that does not validate or was
  /// baked for another skeleton; the codes of si::buildVertexStream, si::buildMorphStream and
  /// si::buildMaterialTable; kBackend on a failed call.
  Status addCharacter(const Character& character, const BakedPalette& palette, CharacterId* out);
  /// Character `id`'s animated impostor atlas, as si::Renderer::buildImpostor makes it
  /// (si/gl/impostor.h says what an impostor keeps and loses; the same desc, cells, views and
  /// frames; supersampled as ImpostorDesc::capture_supersample asks, 2 x 2 by default, and
  /// resolved by the same pass): the atlas image and clip table made here, their capture (the
  /// character drawn once per cell into the atlas's three layers or, supersampled, the
  /// capture's own, averaged into the atlas; the mip chain blitted) recorded by the next
  /// recordUploads(), its temporaries (a depth image and, supersampled, the capture's three
  /// layers: ImpostorInfo::capture_bytes; the capture crowd's records, the coverage's extents)
  /// freed by uploadsComplete(). Each cell's covered
  /// rectangle at each mip level (which cuts the quads) is measured on the GPU in the same
  /// submission (si::gl reads the atlas back; a guest waits for no submission). A crowd of
  /// CrowdDesc::impostor_lod then draws its far instances as impostors on the GPU-driven path,
  /// the quads that cover no pixel centre of the camera's viewport (Camera::
  /// viewport_height_pixels and the projection's aspect) left out on single-sampled renderers.
  /// Building again replaces the atlas: the host has waited for the device's work on the old
  /// one. `info` (when not null) gets the plan, also when refused. kUnsupported without
  /// RendererDesc::gpu_driven (the only path that draws impostors);
  /// kInvalidArgument for an unknown character or a desc si::Renderer refuses; kLimitExceeded
  /// for an atlas past maxImageDimension2D, maxFramebufferWidth/Height or
  /// maxViewportDimensions, more cells than a crowd holds or past ImpostorDesc::max_bytes;
  /// kUnsupported for a device that renders no VK_FORMAT_D32_SFLOAT depth; kBackend naming a
  /// failed call.
  Status buildImpostor(CharacterId id, const ImpostorDesc& desc, ImpostorInfo* info = nullptr);
  /// Whether character `id` has an impostor atlas (buildImpostor).
  bool hasImpostor(CharacterId id) const;
  /// Records the copies of every character added since the last call into `cmd` (outside
  /// rendering: transfers, mip chains, the barriers to the shaders' reads). Nothing to record
  /// is not an error.
  Status recordUploads(VkCommandBuffer cmd);
  /// The host's submission of recordUploads() has completed: its staging buffers are freed.
  void uploadsComplete();

  /// Starts frame slot `frame` (below RendererDesc::frames_in_flight): the draws recorded until
  /// the next beginFrame() write their records into its region of the ring from its start. The
  /// host has waited for the GPU's last frame in that slot. kInvalidArgument past the slots.
  Status beginFrame(uint32_t frame);
  /// The host throws away what it recorded since beginFrame() (a swapchain out of date, an error
  /// of its own) and will not submit it: what the GPU-driven passes recorded in the frame is
  /// forgotten, so their views (and every view of a crowd whose state they copied) start over
  /// at their next passes (the state copied in whole, the LODs seeded, the visibility and motion
  /// history lost); what they held is destroyed once every frame slot has begun again. Call
  /// beginFrame() before recording again. kInvalidArgument without a begun frame.
  Status discardFrame();
  /// Records `view`'s last selection of character `id` with `camera` into `cmd` (inside the
  /// host's dynamic rendering of the formats `target.mode` names, over `target.extent`): one
  /// instanced draw per batch of `batcher` (initialized with batchLimits()), their records
  /// written after the frame's earlier draws' in the slot's region. `camera.depth` says how its
  /// projection's depth is meant: OpenGL's -1 to 1 (si::Camera::lookAt's) is mapped to Vulkan's
  /// 0 to 1; zero-to-one and reverse-Z projections (Camera::lookAtReverseZ, or the engine's own
  /// through Camera::fromMatrices) are used as they are. kInvalidArgument for an unknown
  /// character or mode, no beginFrame(), a batcher not initialized, an empty extent or a
  /// negative offset, a character whose uploads were not recorded, or motion vectors of a view
  /// without previous records; kUnsupported for a view of 2D blends (their third and fourth clips)
  /// or of a crowd with an impostor level (drawn on the GPU-driven path only, so far);
  /// kLimitExceeded when the frame's records pass the slot's region (nothing recorded then).
  /// With motion vectors the view's previous records are copied into the slot's region after
  /// this draw's records; with layered animation its layer records (and previous ones) and the
  /// crowd's mask table follow them.
  Status recordDraw(VkCommandBuffer cmd, const DrawTarget& target, CharacterId id,
                    const CrowdView& view, const InstanceBatcher& batcher, const Camera& camera,
                    DrawStats* stats = nullptr);

  /// The GPU-driven path (RendererDesc::gpu_driven), part 1 of 2: records into `cmd`, outside
  /// rendering and before the rendering that draws it, `view`'s selection of character `id`
  /// with `camera` computed on the GPU, as si::Renderer::drawCrowdGpuCulled computes it (the
  /// same cull, commands and scatter passes: every instance of the view's crowd culled against
  /// the frustum and given its LOD by the view's rules, its record written at the crowd's
  /// clock, bucketed per (LOD, sub-mesh)). The crowd's state is copied in (from a staging
  /// buffer of the frame slot) when it changed: only the instances that changed
  /// (CrowdExport::changedSince), one copy region per run, or the whole state when the buffers
  /// are outgrown or past half the instances changed (`stats`). The state is the crowd's, per
  /// character: its views (a shadow cascade and the main view) share it. The CPU's work does
  /// not depend on the crowd's size otherwise, and the view need not select on the CPU. What a
  /// view keeps on the GPU (its LODs' hysteresis, the passes' output, its ring) is its own. After
  /// beginFrame(), once per view and frame. kInvalidArgument for no beginFrame(), an unknown
  /// character, its uploads not recorded, a detached view, or a crowd of more buckets than
  /// 256 or sub-meshes than the character's, or a crowd with an impostor level
  /// (CrowdDesc::impostor_lod) whose character has no impostor atlas captured (buildImpostor,
  /// then recordUploads); kUnsupported without RendererDesc::gpu_driven, for a crowd that holds
  /// live poses (not built on Vulkan yet), or for impostors with motion vectors (they draw none,
  /// as on si::Renderer); kLimitExceeded when a buffer passes maxStorageBufferRange, the
  /// instances (or a 2D blend's layer compose pass) need more compute groups than the device
  /// has, or the frame's uniforms pass the slot's region. A crowd that plays overlays: the
  /// passes also write each visible instance's layer records, and with 2D blends compose its
  /// masked rows in a pass of their own (si::gl's layer compose pass). A crowd with an impostor
  /// level: the passes also compute each impostor's quad once (si::gl's impostor quads pass), and
  /// the draws draw them after the meshes (one vkCmdDrawIndirect more). With GpuCulling::kOcclusion
  /// the passes are occlusion culling's first phase: draw them, end the rendering, then record
  /// recordGpuDrivenOcclusion() in the same frame.
  Status recordGpuDrivenPasses(VkCommandBuffer cmd, CharacterId id, const CrowdView& view,
                               const Camera& camera, PassStats* stats = nullptr,
                               GpuCulling culling = GpuCulling::kFrustum);
  /// Occlusion culling's second phase: records into `cmd` (outside rendering, after the draws
  /// of `view`'s first phase, passes of GpuCulling::kOcclusion in this frame) the reduction of
  /// `depth` into the view's depth pyramid (R32F, power-of-two sides at least `depth.extent`'s,
  /// a full mip chain: remade when the extent changes) and the passes of the second phase with
  /// the first phase's camera. Then, in a rendering that loads the targets the first phase drew
  /// into, recordGpuDrivenDraw() draws the instances the second phase found visible that the
  /// first did not. The depth is read as the draws wrote it: window depth 0 to 1 of the
  /// camera's convention (greater is farther, or nearer under reverse-Z), the viewport flipped
  /// as the draws flip it. kInvalidArgument for no beginFrame(), an unknown character, a view
  /// whose passes of this frame were not a first phase (or already have their second), a null
  /// depth view, a layout not listed at DepthSource::layout, an empty extent, a negative offset
  /// or samples that are no VkSampleCountFlagBits; kLimitExceeded for a pyramid past
  /// maxImageDimension2D or uniforms past the slot's region; kBackend naming a failed call.
  Status recordGpuDrivenOcclusion(VkCommandBuffer cmd, CharacterId id, const CrowdView& view,
                                  const DepthSource& depth);
  /// Part 2: records the draws of `view`'s passes of this frame into `cmd` (inside the host's
  /// rendering, as recordDraw: `target` says where and what), with the passes' camera: with a
  /// ring (RendererDesc::gpu_driven_ring_bytes) one vkCmdDrawIndexedIndirect of every bucket's
  /// pre-skinned entries, pulled from the ring, then one of every bucket's other entries,
  /// skinned in the vertex stage, each instance's record read through its bucket entry. Any
  /// number of draws (shaded, depth only) of one frame's passes. `stats` counts the draw calls
  /// only: the instances and triangles are the GPU's. kInvalidArgument for an unknown character
  /// or mode, an empty extent or a negative offset, or a view whose passes were not recorded in
  /// this frame; kUnsupported without RendererDesc::gpu_driven.
  Status recordGpuDrivenDraw(VkCommandBuffer cmd, const DrawTarget& target, CharacterId id,
                             const CrowdView& view, DrawStats* stats = nullptr);
  /// The GPU-driven path's device memory now (zero before init()).
  GpuDrivenMemory gpuDrivenMemory() const;
  /// What `view`'s last passes of character `id` counted (both phases, with occlusion culling),
  /// copied by those passes into a host-visible buffer of their frame slot: read after the host
  /// has waited for that frame (and before the slot's next beginFrame()); the renderer cannot
  /// tell otherwise. For tests, tools and statistics: nothing waits. kInvalidArgument before
  /// init(), for a null output, an unknown character or a view whose passes were never
  /// recorded.
  Status readGpuDrivenCounts(CharacterId id, const CrowdView& view, GpuDrivenCounts* out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace si::vk
