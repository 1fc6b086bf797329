// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// What si::vk::Renderer is given at init (si/vk/renderer.h): the host's device and formats, the
/// frames in flight, the record ring, the GPU-driven path and its ring, motion vectors,
/// multisampling.

#include <cstdint>

#include <vulkan/vulkan.h>

#include <glm/glm.hpp>

namespace si::vk {

/// What the renderer is given.
struct RendererDesc {
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;  ///< Required.
  VkDevice device = VK_NULL_HANDLE;                   ///< Required: a Vulkan 1.3 device.
  const VkAllocationCallbacks* allocator = nullptr;   ///< Used for every object it creates.
  VkFormat color_format = VK_FORMAT_R8G8B8A8_UNORM;   ///< The host's colour attachment.
  VkFormat depth_format = VK_FORMAT_D32_SFLOAT;       ///< The host's depth attachment.
  /// The depth attachment of depth-only draws (DrawMode::kDepthOnly: shadow maps, depth
  /// pre-passes); VK_FORMAT_UNDEFINED is depth_format.
  VkFormat depth_only_format = VK_FORMAT_UNDEFINED;
  /// Multisampling: the samples of the host's colour, depth (and motion) attachments that shaded
  /// draws render into (the host resolves them), and of the depth attachment of depth-only draws
  /// (a depth pre-pass of a multisampled target takes `samples`, a shadow map usually 1). init()
  /// refuses a count the device cannot render (framebufferColorSampleCounts,
  /// framebufferDepthSampleCounts) or that is no VkSampleCountFlagBits (kUnsupported).
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
  VkSampleCountFlagBits depth_only_samples = VK_SAMPLE_COUNT_1_BIT;
  /// Motion vectors: VK_FORMAT_UNDEFINED (the default) draws none; a two-channel float format
  /// (VK_FORMAT_R16G16_SFLOAT) makes every shaded draw also write each pixel's motion since the
  /// crowd's previous update into colour attachment 1 of this format, as si::Renderer's
  /// RendererDesc::motion_vectors does (texture coordinate units, now minus then; the crowd
  /// keeps its previous records: CrowdDesc::previous_records). The record ring is then also
  /// read as one storage buffer (kLimitExceeded past the device's maxStorageBufferRange). On
  /// the GPU-driven path every view's passes also write each visible instance's previous record
  /// (what the view drew of it at the crowd's previous step; else its record moved by the
  /// cameras' shift) and the previous positions it pre-skins, as drawCrowdGpuCulled does; the
  /// crowd needs no previous records there, and the motion is since the view's passes of the
  /// crowd's previous step.
  VkFormat motion_format = VK_FORMAT_UNDEFINED;
  uint32_t frames_in_flight = 2;  ///< Frame slots of the record ring (1 to 8).
  /// Bytes of records, per frame slot (rounded up to 256): a frame's batches of every draw
  /// (InstanceBatcher's recordBufferBound) must fit, or recordDraw() refuses the frame
  /// (kLimitExceeded).
  uint64_t ring_bytes_per_frame = uint64_t(8) << 20;
  /// Morph targets at coarse LOD levels: the share of a level's error its vertices may leave
  /// out of their targets (si::Renderer's RendererDesc::morph_lod_share), 0 to 1.
  float morph_lod_share = 0.5f;
  /// The direction the light travels along, world space (si::Renderer's default).
  glm::vec3 light_direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
  /// The GPU-driven path (recordGpuDrivenPasses, recordGpuDrivenDraw). The host created its
  /// device with the features shaderFloat64, multiDrawIndirect and drawIndirectFirstInstance
  /// enabled (the cull pass keeps the crowd's clock and positions in doubles, as the CPU does):
  /// init() refuses a physical device without them (kUnsupported).
  bool gpu_driven = false;
  /// The GPU-driven path's pre-skinning: bytes of each view's ring of pre-skinned vertices (16
  /// a vertex, and 4 more for a character with tangents), within maxStorageBufferRange. The
  /// passes skin the visible instances' vertices into it in compute, bucket by bucket as far as
  /// it holds them, and the draw pulls them; the rest are skinned in the vertex stage. 0: every
  /// instance skinned in the vertex stage (no ring). The passes refuse a ring that does not
  /// hold one instance of the largest LOD (kLimitExceeded).
  uint64_t gpu_driven_ring_bytes = uint64_t(256) << 20;
  /// The GPU-driven path keeps a view's buffers (and a crowd's state, while no view keeps it)
  /// until this many beginFrame() calls pass without passes of it; then they are freed (a view
  /// or crowd that is gone leaves nothing behind; one that comes back starts over: its state
  /// copied in whole, its LODs seeded again). 0: kept until shutdown().
  uint32_t gpu_driven_idle_frames = 240;
};

}  // namespace si::vk
