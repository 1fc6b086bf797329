// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// One character's impostor atlas on the host's device (vk::Renderer::buildImpostor), as si::gl's
// ImpostorAtlas holds it: the image of three layers (base colour and coverage; normal and tint
// mask; metallic, roughness, occlusion and the material's code) with its mip chain, the clip table
// the impostor shaders find frames and covered rectangles in, and the numbers their uniforms
// carry; and the capture that fills it, staged by buildImpostor and recorded by recordUploads:
// the capture crowd's records, one instanced draw per batch into the three layers, the mip chain
// blitted, the clip table copied.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/impostor_plan.h"
#include "vk/device_objects.h"

namespace si::vk::detail {

struct ImpostorAtlas : si::detail::ImpostorGrid {
  static constexpr uint32_t kLayers = 3;
  /// The atlas's depth attachment while it is captured.
  static constexpr VkFormat kCaptureDepthFormat = VK_FORMAT_D32_SFLOAT;

  GpuImage image;  ///< VK_FORMAT_R8G8B8A8_UNORM, kLayers layers, every mip level; a 2D array view.
  /// Per clip (first texel, frames, first cell frame, frames), then per cell and mip level its
  /// covered rectangle (impostor_quad.glsl's SiImpostorClips).
  GpuBuffer clips;
  bool captured = false;  ///< recordUploads() recorded its capture.

  bool made() const { return image.image != VK_NULL_HANDLE; }
};

/// The capture waiting for recordUploads(): what it draws with, freed by uploadsComplete().
struct ImpostorCapture {
  /// One instanced draw of the capture crowd: its index range, instances and dynamic offsets
  /// (the instanced layout's, in binding order, into `staging`).
  struct Draw {
    uint32_t first_index = 0, index_count = 0, instances = 0;
    std::vector<uint32_t> offsets;
  };
  GpuImage depth;  ///< kCaptureDepthFormat, the atlas's level-0 size.
  VkImageView layers[ImpostorAtlas::kLayers] = {};  ///< Level 0 of each layer, the attachments.
  /// Host-visible: the records and default blocks the draws read, then the clip table's contents
  /// (at `table_at`).
  GpuBuffer staging;
  VkDeviceSize table_at = 0;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;  ///< The capture program of the character's mesh.
  std::vector<Draw> draws;
  /// The covered rectangles' measure (impostor_coverage.comp.glsl): the extents it gathers, its
  /// set, and per level (then the packing pass) its uniforms' offset in `staging` and groups.
  GpuBuffer extents;
  VkDescriptorPool coverage_pool = VK_NULL_HANDLE;
  VkDescriptorSet coverage_set = VK_NULL_HANDLE;
  struct CoveragePass {
    uint32_t defaults_at = 0, groups_x = 1, groups_y = 1;
  };
  std::vector<CoveragePass> coverage;  ///< One per level, then the packing pass.

  bool pending() const { return pipeline != VK_NULL_HANDLE; }
};

/// The coverage passes' pipelines and layout (impostor_passes.h's).
struct CoveragePipelines {
  VkPipeline extents, rects;
  VkPipelineLayout layout;
};

/// Records `capture` into `cmd` (outside rendering): the three layers and the depth cleared
/// (to zero and the far plane), the draws with `pipeline_layout` and the character's `vertices`
/// and `indices` through an unflipped viewport (the atlas's rows bottom up, as OpenGL's texture
/// holds them: texture coordinates read both alike), the mip chain blitted and left for the
/// fragment and compute stages, the clip table copied, then every cell's covered rectangle at
/// every level measured into it by the `coverage` passes (the extents of each level, then the
/// rectangles), left for the vertex and compute stages.
void recordImpostorCapture(VkCommandBuffer cmd, const ImpostorCapture& capture,
                           VkPipelineLayout pipeline_layout, VkBuffer vertices, VkBuffer indices,
                           const CoveragePipelines& coverage, ImpostorAtlas* atlas);

/// Destroys what `capture` holds (the host's submission of its recording has completed, or it
/// was never recorded).
void releaseImpostorCapture(DeviceObjects* objects, ImpostorCapture* capture);
/// Destroys the atlas's image and clip table.
void releaseImpostorAtlas(DeviceObjects* objects, ImpostorAtlas* atlas);

}  // namespace si::vk::detail
