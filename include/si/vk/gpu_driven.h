// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The GPU-driven path's types (si::vk::Renderer::recordGpuDrivenPasses, recordGpuDrivenOcclusion,
/// readGpuDrivenCounts, gpuDrivenMemory; si/vk/renderer.h): how a view is culled, the host's
/// depth that occlusion culling reads, and what the passes copied, counted and hold.

#include <cstdint>

#include <vulkan/vulkan.h>

namespace si::vk {

/// How recordGpuDrivenPasses() culls a view.
enum class GpuCulling : uint8_t {
  /// Against the frustum and the view's range: the draws that follow draw the view's selection.
  kFrustum = 0,
  /// Two-phase occlusion culling (si::Renderer's RendererDesc::gpu_occlusion_culling). These
  /// passes are the first phase: the instances in the frustum that were visible at the end of
  /// the view's last frame, which the draws that follow draw into the host's depth. Then,
  /// outside rendering, recordGpuDrivenOcclusion() reduces that depth (with whatever the host
  /// drew into it before, with the same camera) into a depth pyramid and records the second
  /// phase: every instance in the frustum tested against it (its clip's bounding box); those
  /// not occluded are visible next frame, and the draws after it draw those the first phase did
  /// not. The image is the one drawn without occlusion culling. A view's first frame (or one
  /// after its crowd was reshaped) has no history: the first phase draws nothing.
  kOcclusion,
};

/// The host's depth as occlusion culling's second phase reads it (recordGpuDrivenOcclusion()).
struct DepthSource {
  /// A view of the depth aspect alone of the depth attachment the first phase drew into (an
  /// image made with VK_IMAGE_USAGE_SAMPLED_BIT), single-sampled or multisampled (each pixel's
  /// farthest sample is kept).
  VkImageView view = VK_NULL_HANDLE;
  /// The layout the host put it in for compute shaders to read:
  /// VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL (the default),
  /// VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_READ_ONLY_OPTIMAL,
  /// VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL or VK_IMAGE_LAYOUT_GENERAL; the host's barrier
  /// made the rendering's depth writes visible to VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT's
  /// VK_ACCESS_SHADER_READ_BIT.
  VkImageLayout layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
  /// The area the first phase's draws covered: their DrawTarget::extent and offset.
  VkExtent2D extent{0, 0};
  VkOffset2D offset{0, 0};
  /// The image's samples, as it was made (RendererDesc::samples for the main view's depth).
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
};

/// What recordGpuDrivenPasses() recorded of the crowd's state: the bytes of instance state it
/// copied in (0 when nothing changed since the crowd's last passes, in any view; while some
/// instance holds an overlay, each changed instance's overlay state too), in how many copy
/// regions of instance state (one per run of changed instances), and whether it copied the whole
/// state (the crowd, its shape or its size outgrew the buffers, or past half its instances
/// changed).
struct PassStats {
  uint64_t state_bytes_uploaded = 0;
  uint32_t upload_regions = 0;
  bool whole_upload = false;
};

/// The GPU-driven path's device memory: the crowds' state (shared by each crowd's views) and the
/// views' own buffers (LODs, the passes' output, the pre-skinning ring).
struct GpuDrivenMemory {
  uint32_t crowds = 0, views = 0;
  uint64_t crowd_bytes = 0, view_bytes = 0;
};

/// What the GPU-driven passes of a view counted (readGpuDrivenCounts), as si::Renderer's
/// DrawStats counts them for drawCrowdGpuCulled.
struct GpuDrivenCounts {
  uint32_t visible = 0;                  ///< Instances selected (in the frustum and range).
  uint64_t instances = 0;                ///< Instance-draws: one per worn sub-mesh drawn.
  uint64_t triangles = 0;                ///< Triangles drawn.
  uint64_t pre_skinned_vertices = 0;     ///< Vertices pre-skinned into the ring,
  uint64_t vertex_shader_instances = 0;  ///< and instance-draws skinned in the vertex stage.
  /// Impostors whose quad covers no pixel centre of the camera's viewport, left out (not in
  /// `instances` or `triangles`), as si::gl's DrawStats::impostors_left_out.
  uint64_t impostors_left_out = 0;
};

}  // namespace si::vk
