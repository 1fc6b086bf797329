// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A character's buffers, images and staging for the Vulkan back-end.
#include "vk/character_resources.h"

#include <array>

#include <algorithm>
#include <cstring>

#include "core/gpu_material.h"
#include "core/str_cat.h"
#include "si/core/material_table.h"

namespace si::vk::detail {

using si::detail::GpuMaterial;
using si::detail::gpuMaterial;
using si::detail::strCat;

Status stageCharacter(DeviceObjects* objects, const Character& character,
                      const BakedPalette& palette, const StagingLimits& limits,
                      CharacterResources* c, VertexStream* stream_out) {
  const SkinnedMesh& mesh = character.mesh;
  Status s = palette.validate();
  if (!s.isOk()) return {StatusCode::kInvalidArgument, "the palette: " + s.message()};
  if (palette.skeleton_to_palette.size() != character.skeleton.jointCount())
    return {StatusCode::kInvalidArgument, "the palette was baked for another skeleton"};
  VertexStream& stream = *stream_out;
  s = buildVertexStream(mesh, palette, &stream);
  // Morph targets: their entries in an RGBA32UI image, each LOD level's cut (si::gl's too).
  MorphStream morphs;
  std::array<float, kMorphLodCuts> cuts{};
  if (s.isOk() && !mesh.morph_targets.empty())
    s = buildMorphStream(mesh, palette, limits.max_image_size, &morphs);
  if (s.isOk() && !mesh.morph_targets.empty())
    s = morphLodCuts(mesh, limits.morph_lod_share, &cuts);
  MaterialTable table;
  if (s.isOk()) s = buildMaterialTable(character, limits.max_image_size, &table);
  if (!s.isOk()) return s;
  if (table.data_layers.empty()) {  // A flat normal, as si::gl's: one layer to bind.
    Image flat;
    flat.width = flat.height = 1;
    flat.rgba8 = {128, 128, 255, 255};
    table.data_layers.push_back(flat);
    table.data_width = table.data_height = 1;
  }
  std::vector<uint32_t> vertex_words((table.vertex_materials.size() + 1) / 2, 0);
  for (size_t v = 0; v < table.vertex_materials.size(); ++v)
    vertex_words[v / 2] |= uint32_t(table.vertex_materials[v]) << ((v % 2) * 16);
  std::vector<GpuMaterial> entries;
  for (const MaterialEntry& e : table.materials)
    entries.push_back(gpuMaterial(e, si::detail::vertexWordBits(stream)));
  // SiPaletteInfo: si_palette_info, si_morph_info, si_morph_cuts[2] (std140: 4 x 16 bytes).
  glm::uvec4 info_block[4] = {
      paletteShaderInfo(palette),
      morphs.texels.empty() ? glm::uvec4(0u) : morphShaderInfo(palette, morphs), glm::uvec4(0u),
      glm::uvec4(0u)};
  static_assert(sizeof(cuts) == 2 * sizeof(glm::uvec4), "two vec4 of cuts");
  std::memcpy(&info_block[2], cuts.data(), sizeof(cuts));

  c->sub_meshes = mesh.sub_meshes;
  c->frame_stride_texels = palette.layout.frame_stride_texels;
  // Pre-skinning's lists (the GPU-driven path's ring) and how its passes read the stream.
  si::detail::buildPreSkinLists(mesh, &c->pre_skin);
  c->source_words =
      si::detail::preSkinSourceWords(stream) | (stream.tangent_offset != 0 ? 0x200u : 0u);
  c->tangents = stream.tangent_offset != 0;
  // The staging buffer: every content, each at a 16-byte offset.
  struct Content {
    const void* data;
    size_t bytes;
  };
  std::vector<Content> contents;
  const auto layerBytes = [](const std::vector<Image>& layers) {
    size_t n = 0;
    for (const Image& i : layers) n += i.rgba8.size();
    return n;
  };
  const bool half = palette.format == PaletteFormat::kMatrix3x4F16;
  const VkBufferUsageFlags dst = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  const struct {
    GpuBuffer* buffer;
    VkBufferUsageFlags usage;
    const void* data;
    size_t bytes;
    const char* what;
  } buffers[] = {
      // Also read as words by the GPU-driven pre-skinning pass and pre-skinned draw.
      {&c->vertices, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
       stream.bytes.data(), stream.bytes.size(), "the character's vertex buffer"},
      {&c->indices, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, mesh.indices.data(), mesh.indices.size() * 4,
       "the character's index buffer"},
      {&c->palette_info, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, info_block, sizeof(info_block),
       "the palette's info block"},
      {&c->vertex_materials, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vertex_words.data(),
       vertex_words.size() * 4, "the character's per-vertex materials"},
      {&c->materials, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, entries.data(),
       entries.size() * sizeof(GpuMaterial), "the character's material table"},
      {&c->lod_vertices, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, c->pre_skin.lod_vertices.data(),
       c->pre_skin.lod_vertices.size() * 4, "pre-skinning's vertex lists"},
      {&c->local_indices, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, c->pre_skin.local_indices.data(),
       c->pre_skin.local_indices.size() * 4, "pre-skinning's re-indexed triangles"},
  };
  for (const auto& b : buffers) {
    if (!s.isOk()) break;
    s = objects->createBuffer(std::max<size_t>(b.bytes, 4), b.usage | dst, false, b.what, b.buffer);
    contents.push_back({b.data, b.bytes});
  }
  if (s.isOk())
    s = objects->createImage(palette.layout.width, palette.layout.height, 1, 1,
                             half ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT,
                             false, "the palette texture", &c->palette);
  if (s.isOk())
    s = objects->createImage(table.width, table.height, uint32_t(table.layers.size()),
                             mipLevels(table.width, table.height), VK_FORMAT_R8G8B8A8_SRGB, true,
                             "the character's colour texture array", &c->base_color);
  if (s.isOk())
    s = objects->createImage(
        table.data_width, table.data_height, uint32_t(table.data_layers.size()),
        mipLevels(table.data_width, table.data_height), VK_FORMAT_R8G8B8A8_UNORM, true,
        "the character's data texture array", &c->material_data);
  if (s.isOk() && !morphs.texels.empty())
    s = objects->createImage(morphs.width, morphs.height, 1, 1, VK_FORMAT_R32G32B32A32_UINT, false,
                             "the character's morph targets", &c->morphs);
  VkDeviceSize staging_bytes = 0;
  for (const Content& k : contents) staging_bytes = alignUp(staging_bytes + k.bytes, 16);
  const VkDeviceSize morphs_at = staging_bytes;
  staging_bytes = alignUp(staging_bytes + morphs.texels.size() * 4, 16);
  const VkDeviceSize palette_at = staging_bytes;
  staging_bytes = alignUp(staging_bytes + palette.texel_bytes.size(), 16);
  const VkDeviceSize colour_at = staging_bytes;
  staging_bytes = alignUp(staging_bytes + layerBytes(table.layers), 16);
  const VkDeviceSize data_at = staging_bytes;
  staging_bytes += layerBytes(table.data_layers);
  if (s.isOk())
    s = objects->createBuffer(staging_bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true,
                              "the character's staging", &c->staging);
  if (s.isOk()) {
    uint8_t* to = static_cast<uint8_t*>(c->staging.mapped);
    VkDeviceSize at = 0;
    for (size_t k = 0; k < contents.size(); ++k) {
      if (contents[k].bytes > 0) std::memcpy(to + at, contents[k].data, contents[k].bytes);
      c->buffer_uploads.push_back({buffers[k].buffer, at});
      at = alignUp(at + contents[k].bytes, 16);
    }
    std::memcpy(to + palette_at, palette.texel_bytes.data(), palette.texel_bytes.size());
    if (!morphs.texels.empty())
      std::memcpy(to + morphs_at, morphs.texels.data(), morphs.texels.size() * 4);
    VkDeviceSize layer_at = colour_at;
    for (const Image& i : table.layers) {
      std::memcpy(to + layer_at, i.rgba8.data(), i.rgba8.size());
      layer_at += i.rgba8.size();
    }
    layer_at = data_at;
    for (const Image& i : table.data_layers) {
      std::memcpy(to + layer_at, i.rgba8.data(), i.rgba8.size());
      layer_at += i.rgba8.size();
    }
    c->image_uploads = {{&c->palette, palette_at, false},
                        {&c->base_color, colour_at, true},
                        {&c->material_data, data_at, true}};
    if (!morphs.texels.empty()) c->image_uploads.push_back({&c->morphs, morphs_at, false});
  }
  if (!s.isOk()) destroyCharacter(objects, c);
  return s;
}

void destroyCharacter(DeviceObjects* objects, CharacterResources* c) {
  for (GpuBuffer* b : {&c->vertices, &c->indices, &c->palette_info, &c->vertex_materials,
                       &c->materials, &c->lod_vertices, &c->local_indices, &c->staging})
    objects->destroy(b);
  for (GpuImage* i : {&c->palette, &c->base_color, &c->material_data, &c->morphs})
    objects->destroy(i);
  const auto destroy_pipeline = [&](VkPipeline& p) {
    if (p != VK_NULL_HANDLE) vkDestroyPipeline(objects->device(), p, objects->allocator());
    p = VK_NULL_HANDLE;
  };
  for (auto& by_kind : c->pipelines)
    for (VkPipeline& p : by_kind) destroy_pipeline(p);
  for (auto& by_kind : c->driven_pipelines)
    for (VkPipeline& p : by_kind) destroy_pipeline(p);
  for (VkPipeline& p : c->pulled_pipelines) destroy_pipeline(p);
  for (auto& by_motion : c->skin_pipelines)
    for (VkPipeline& p : by_motion) destroy_pipeline(p);
  for (VkPipeline& p : c->compose_pipelines) destroy_pipeline(p);
  if (c->pool != VK_NULL_HANDLE)
    vkDestroyDescriptorPool(objects->device(), c->pool, objects->allocator());
  c->pool = VK_NULL_HANDLE;
  releaseImpostorCapture(objects, &c->capture);
  releaseImpostorAtlas(objects, &c->impostor);
}

}  // namespace si::vk::detail
