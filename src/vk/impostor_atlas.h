// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// One character's impostor atlas on the host's device (vk::Renderer::buildImpostor), as si::gl's
// ImpostorAtlas holds it: the image of three layers (base colour and coverage; normal and tint
// mask; metallic, roughness, occlusion and the material's code) with its mip chain, the clip table
// the impostor shaders find frames and covered rectangles in, and the numbers their uniforms
// carry; and the capture that fills it, staged by buildImpostor and recorded by recordUploads:
// the capture crowd's records, one instanced draw per batch into the three layers (the atlas's,
// or, supersampled, the capture's own, averaged into the atlas by the resolve pass as si::gl's
// resources/impostor_resolve.h does), the mip chain blitted, the clip table copied.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/impostor_plan.h"
#include "vk/device_objects.h"
#include "vk/impostor_passes.h"

namespace si::vk::detail {

struct ImpostorAtlas : si::detail::ImpostorGrid {
  static constexpr uint32_t kLayers = 3;
  /// The layer of metallic, roughness, occlusion and the material's code.
  static constexpr uint32_t kSurfaceLayer = 2;
  /// The atlas's depth attachment while it is captured.
  static constexpr VkFormat kCaptureDepthFormat = VK_FORMAT_D32_SFLOAT;

  GpuImage image;  ///< VK_FORMAT_R8G8B8A8_UNORM, kLayers layers, every mip level; a 2D array view.
  /// Per clip (first texel, frames, first cell frame, frames), then per cell and mip level its
  /// covered rectangle (impostor_quad.glsl's SiImpostorClips).
  GpuBuffer clips;
  /// Trilinear, clamped to the edges, with ImpostorDesc::lod_bias: what the impostor draws read
  /// the atlas through.
  VkSampler sampler = VK_NULL_HANDLE;
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
  GpuImage depth;  ///< kCaptureDepthFormat, the capture's size.
  /// Level 0 of each layer the capture draws into (the atlas's, or `supersampled`'s).
  VkImageView layers[ImpostorAtlas::kLayers] = {};
  /// Capture texels each way per atlas texel (ImpostorInfo::capture_supersample). Past 1 the
  /// capture draws into `supersampled` (its three layers, `factor` times the atlas's sides), and
  /// the resolve pass averages them into the atlas's level 0 (`atlas_level0`, a storage image)
  /// through `resolve_set`: every layer's means before the mip chain, then the surface layer's
  /// one material (resolve_at: the two dispatches' uniforms in `staging`).
  uint32_t factor = 1;
  GpuImage supersampled;
  VkImageView atlas_level0 = VK_NULL_HANDLE;
  VkDescriptorPool resolve_pool = VK_NULL_HANDLE;
  VkDescriptorSet resolve_set = VK_NULL_HANDLE;
  uint32_t resolve_at[2] = {};
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

/// Records `capture` into `cmd` (outside rendering): the three layers and the depth cleared
/// (to zero and the far plane), the draws with `pipeline_layout` and the character's `vertices`
/// and `indices` through an unflipped viewport (the atlas's rows bottom up, as OpenGL's texture
/// holds them: texture coordinates read both alike), supersampled the layers resolved into the
/// atlas's level 0 by `passes`' resolve pass, the mip chain blitted (then, supersampled, the
/// surface layer's level 0 resolved again as one material's) and left for the fragment and
/// compute stages, the clip table copied, then every cell's covered rectangle at every level
/// measured into it by `passes`' coverage passes (the extents of each level, then the
/// rectangles), left for the vertex and compute stages.
void recordImpostorCapture(VkCommandBuffer cmd, const ImpostorCapture& capture,
                           VkPipelineLayout pipeline_layout, VkBuffer vertices, VkBuffer indices,
                           const ImpostorPasses& passes, ImpostorAtlas* atlas);

/// Destroys what `capture` holds (the host's submission of its recording has completed, or it
/// was never recorded).
void releaseImpostorCapture(DeviceObjects* objects, ImpostorCapture* capture);
/// Destroys the atlas's image and clip table.
void releaseImpostorAtlas(DeviceObjects* objects, ImpostorAtlas* atlas);

}  // namespace si::vk::detail
