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

#include "vk/device_objects.h"

namespace si::vk::detail {

struct ImpostorAtlas {
  static constexpr uint32_t kLayers = 3;
  /// The atlas's depth attachment while it is captured.
  static constexpr VkFormat kCaptureDepthFormat = VK_FORMAT_D32_SFLOAT;

  GpuImage image;  ///< VK_FORMAT_R8G8B8A8_UNORM, kLayers layers, every mip level; a 2D array view.
  /// Per clip (first texel, frames, first cell frame, frames), then per cell and mip level its
  /// covered rectangle (impostor_quad.glsl's SiImpostorClips).
  GpuBuffer clips;
  uint32_t clip_count = 0;
  uint32_t columns = 0, rows = 0;  ///< Cells across and down.
  uint32_t azimuths = 0, elevations = 0;
  float elevations_radians[4] = {};
  uint32_t frame_stride_texels = 0;  ///< The palette's.
  glm::vec3 centre{0.0f};            ///< The cell's centre in model units.
  float cell_units = 0.0f;           ///< The cell's side in model units.
  uint32_t cell_texels = 0;          ///< The cell's side in level-0 texels.
  bool captured = false;             ///< recordUploads() recorded its capture.

  bool made() const { return image.image != VK_NULL_HANDLE; }
  /// Its shaders' uniforms (u_impostor_grid, _counts, _elevations, _cell).
  glm::uvec4 grid() const { return {columns, rows, azimuths, elevations}; }
  glm::uvec4 counts() const {
    return {clip_count, frame_stride_texels, azimuths * elevations, image.levels};
  }
  glm::vec4 cell() const { return {centre, cell_units}; }
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

  bool pending() const { return pipeline != VK_NULL_HANDLE; }
};

/// Records `capture` into `cmd` (outside rendering): the three layers and the depth cleared
/// (to zero and the far plane), the draws with `pipeline_layout` and the character's `vertices`
/// and `indices` through an unflipped viewport (the atlas's rows bottom up, as OpenGL's texture
/// holds them: texture coordinates read both alike), the mip chain blitted and left for the
/// fragment stage, the clip table copied and left for the vertex and compute stages.
void recordImpostorCapture(VkCommandBuffer cmd, const ImpostorCapture& capture,
                           VkPipelineLayout pipeline_layout, VkBuffer vertices, VkBuffer indices,
                           ImpostorAtlas* atlas);

/// Destroys what `capture` holds (the host's submission of its recording has completed, or it
/// was never recorded).
void releaseImpostorCapture(DeviceObjects* objects, ImpostorCapture* capture);
/// Destroys the atlas's image and clip table.
void releaseImpostorAtlas(DeviceObjects* objects, ImpostorAtlas* atlas);

}  // namespace si::vk::detail
