// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// One character on the host's device for the Vulkan back-end: its vertex stream and indices,
// palette and palette info, material table and texture arrays (as si::gl's CharacterBuffers and
// PaletteTexture upload them), the staging that fills them (recorded by Renderer::
// recordUploads), and its pipeline and descriptor set (made by the renderer).

#include <vulkan/vulkan.h>

#include <vector>

#include "core/pre_skin_lists.h"
#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/core/shader_inputs.h"
#include "vk/device_objects.h"
#include "vk/image_upload.h"
#include "vk/impostor_atlas.h"
#include "vk/vulkan_programs.h"

namespace si::vk::detail {

/// A buffer's contents waiting in the staging buffer from `offset`.
struct BufferUpload {
  GpuBuffer* buffer;
  VkDeviceSize offset;
};

/// How a GPU-driven draw and pre-skinning pass skin a crowd's layered animation: not at all (no
/// overlay), the overlays composed per vertex, or the rows of the layer compose pass read (2D
/// blends).
enum Layering : uint8_t { kNoLayers = 0, kLayersPerVertex = 1, kComposedLayers = 2 };

struct CharacterResources {
  GpuBuffer vertices, indices, palette_info, vertex_materials, materials;
  /// Pre-skinning's lists (the GPU-driven path): each local vertex's source vertex, and the
  /// triangles re-indexed to their list (an index buffer); where each (sub-mesh, LOD)'s are, and
  /// pre_skin_common.glsl's u_layout.y (| 0x200 when the stream has tangents: the tangent ring
  /// is written and read).
  GpuBuffer lod_vertices, local_indices;
  si::detail::PreSkinListData pre_skin;
  uint32_t source_words = 0;
  bool tangents = false;
  GpuImage palette, base_color, material_data;
  GpuImage morphs;  ///< Morph targets (MorphStream's texels); none without.
  std::vector<SubMesh> sub_meshes;
  /// The index range of `sub_mesh` at `lod` (its last LOD when `lod` is past it), as si::gl's
  /// CharacterBuffers::lodRange.
  IndexRange lodRange(uint32_t sub_mesh, uint32_t lod) const {
    const std::vector<IndexRange>& lods = sub_meshes[sub_mesh].lods;
    return lods[lod < lods.size() ? lod : lods.size() - 1];
  }
  uint32_t frame_stride_texels = 0;  ///< The palette's (the GPU-driven cull pass's records).
  /// Without and with layers, by VulkanKind: the program (its index in vulkanPrograms(), the
  /// mesh's variant) and the pipeline (the motion ones only when the renderer draws motion
  /// vectors).
  uint32_t programs[2][kVulkanKinds] = {};
  VkPipeline pipelines[2][kVulkanKinds] = {};
  /// The GPU-driven draw's programs and pipelines, without layers, with layers and with composed
  /// layers (by Layering), shaded, depth only
  /// and with motion vectors (by VulkanKind; made when the renderer draws the GPU-driven path,
  /// the last with motion vectors).
  uint32_t driven_programs[3][kVulkanKinds] = {};
  VkPipeline driven_pipelines[3][kVulkanKinds] = {};
  /// Its pre-skinned draws (the same kinds), and its pre-skinning pass (compute) by Layering,
  /// alone and also skinning the previous positions (motion vectors: made only when the renderer
  /// draws them); the layer compose pass of its mesh, alone and with the previous records.
  uint32_t pulled_programs[kVulkanKinds] = {};
  VkPipeline pulled_pipelines[kVulkanKinds] = {};
  uint32_t skin_programs[3][2] = {};
  VkPipeline skin_pipelines[3][2] = {};
  uint32_t compose_programs[2] = {};
  VkPipeline compose_pipelines[2] = {};
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
  /// The vertex stream's format and the mesh's program variant (the impostor capture's pipeline
  /// is made with them).
  VertexStream stream;
  MeshVariant variant;
  const BakedPalette* palette_source = nullptr;  ///< The host's, alive while it is drawn.
  /// Its impostor atlas (Renderer::buildImpostor), and the capture recordUploads() records.
  ImpostorAtlas impostor;
  ImpostorCapture capture;
  GpuBuffer staging;  ///< Until recordUploads() hands it on.
  std::vector<BufferUpload> buffer_uploads;
  std::vector<ImageUpload> image_uploads;
  bool uploads_recorded = false;
};

/// What staging a character is bounded by: the device's largest 2D image side (the material
/// arrays' and morph image's), and RendererDesc::morph_lod_share.
struct StagingLimits {
  uint32_t max_image_size = 0;
  float morph_lod_share = 0.5f;
};

/// Creates `c`'s buffers and images for `character` and `palette` (its morph targets' image
/// too) and fills its staging buffer with their contents (the upload lists say where), and sets
/// `*stream` to the vertex stream (the pipeline's vertex format). kInvalidArgument for a
/// palette that does not validate or was baked for another skeleton; the codes of
/// si::buildVertexStream, si::buildMorphStream, si::morphLodCuts and si::buildMaterialTable;
/// kBackend on a failed call. Nothing is kept on failure.
Status stageCharacter(DeviceObjects* objects, const Character& character,
                      const BakedPalette& palette, const StagingLimits& limits,
                      CharacterResources* c, VertexStream* stream);

/// Destroys what `c` holds (its pipelines and descriptor pool too).
void destroyCharacter(DeviceObjects* objects, CharacterResources* c);

}  // namespace si::vk::detail
