// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Uploading the character: vertex stream, indices, vertex format, base colour texture.
#include "gl/resources/character_buffers.h"

#include <algorithm>
#include <cmath>

#include "core/gpu_material.h"
#include "core/str_cat.h"
#include "gl/profile/gl_profile.h"
#include "gl/programs/program_catalog.h"
#include "gl/resources/gl_allocation.h"
#include "si/core/material_table.h"
#include "si/core/shader_inputs.h"

namespace si::detail {

namespace {

Status uploadLayers(GLuint* texture, GLenum format, const std::vector<Image>& layers,
                    uint32_t width, uint32_t height, const char* what) {
  const GLsizei w = GLsizei(width), h = GLsizei(height);
  const GLsizei levels = GLsizei(std::floor(std::log2(double(std::max(w, h))))) + 1;
  Status s = createTexture2DArray(texture, levels, format, w, h, GLsizei(layers.size()), what);
  if (!s.isOk()) return s;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (size_t l = 0; l < layers.size(); ++l)
    glTextureSubImage3D(*texture, 0, 0, 0, GLint(l), w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                        layers[l].rgba8.data());
  glGenerateTextureMipmap(*texture);
  glTextureParameteri(*texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(*texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return Status::ok();
}

}  // namespace

Status CharacterBuffers::upload(const Character& character, const BakedPalette& palette,
                                uint32_t max_texture_size, float morph_lod_share) {
  const SkinnedMesh& m = character.mesh;
  Status s = m.validate(character.skeleton.jointCount());
  if (!s.isOk()) return s;
  if (palette.skeleton_to_palette.size() != character.skeleton.jointCount())
    return {StatusCode::kInvalidArgument, "the palette was baked for another skeleton"};
  VertexStream stream;
  s = buildVertexStream(m, palette, &stream);
  MorphStream morphs;
  std::array<float, kMorphLodCuts> cuts{};
  if (s.isOk() && !m.morph_targets.empty())
    s = buildMorphStream(m, palette, max_texture_size == 0 ? 16384 : max_texture_size, &morphs);
  if (s.isOk() && !m.morph_targets.empty()) s = morphLodCuts(m, morph_lod_share, &cuts);
  MaterialTable table;
  if (s.isOk()) s = buildMaterialTable(character, max_texture_size, &table);
  if (!s.isOk()) return s;
  release();
  s = createBuffer(&vertex_buffer, stream.bytes.size(), stream.bytes.data(), 0,
                   "the character's vertex buffer");
  if (s.isOk())
    s = createIndexBuffer(&index_buffer, m.indices.size() * 4, m.indices.data(),
                          "the character's index buffer");
  if (s.isOk()) s = uploadMaterials(&table, stream);
  if (s.isOk() && !morphs.texels.empty()) {
    s = createTexture2D(&morph_texture, 1, GL_RGBA32UI, GLsizei(morphs.width),
                        GLsizei(morphs.height), "the character's morph targets");
    if (s.isOk()) {
      glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
      glTextureSubImage2D(morph_texture, 0, 0, 0, GLsizei(morphs.width), GLsizei(morphs.height),
                          GL_RGBA_INTEGER, GL_UNSIGNED_INT, morphs.texels.data());
      glTextureParameteri(morph_texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTextureParameteri(morph_texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
  }
  if (!s.isOk()) {
    release();
    return s;
  }
  morph_offset = stream.morph_offset;
  morph_info = morphs.texels.empty() ? glm::uvec4(0u) : morphShaderInfo(palette, morphs);
  morph_cuts = cuts;
  wide_joints = stream.wide_joints;
  stride_bytes = stream.stride_bytes;
  sub_meshes = m.sub_meshes;
  vertex_count = uint32_t(m.vertexCount());
  mesh = m;
  tangent_offset = stream.tangent_offset;
  texcoord1_offset = stream.texcoord1_offset;
  color_offset = stream.color_offset;
  joints1_offset = stream.joints1_offset;
  weights1_offset = stream.weights1_offset;
  glCreateVertexArrays(1, &vao);
  describeVertexFormat(vao);
  return Status::ok();
}

Status CharacterBuffers::uploadMaterials(MaterialTable* table, const VertexStream& stream) {
  // Each vertex's material index (16 bits, two a word), the table, the texture arrays.
  std::vector<uint32_t> words((table->vertex_materials.size() + 1) / 2, 0);
  for (size_t v = 0; v < table->vertex_materials.size(); ++v)
    words[v / 2] |= uint32_t(table->vertex_materials[v]) << ((v % 2) * 16);
  std::vector<GpuMaterial> entries;
  double_sided = alpha_masked = false;
  const uint32_t vertex_words = vertexWordBits(stream);
  for (const MaterialEntry& e : table->materials) {
    entries.push_back(gpuMaterial(e, vertex_words));
    double_sided = double_sided || e.double_sided;
    alpha_masked = alpha_masked || e.alpha_cutoff >= 0.0f;
  }
  Status s;
  if (esProfile()) {
    // A uniform block of kEsMaxMaterials entries there; the bound buffer holds it whole (WebGL 2
    // refuses a draw whose uniform buffer is smaller than its block).
    if (entries.size() > kEsMaxMaterials)
      s = {StatusCode::kLimitExceeded,
           strCat(entries.size(), " materials (the OpenGL ES profile's material block holds ",
                  kEsMaxMaterials, ")")};
    entries.resize(kEsMaxMaterials, gpuMaterial(MaterialEntry{}, 0u));
  }
  if (s.isOk())
    s = createBuffer(&vertex_materials, words.size() * 4, words.data(), 0,
                     "the character's per-vertex materials");
  if (s.isOk())
    s = createBuffer(&material_table, entries.size() * sizeof(GpuMaterial), entries.data(), 0,
                     "the character's material table");
  GLint max_layers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
  for (const size_t layers : {table->layers.size(), table->data_layers.size()})
    if (s.isOk() && layers > size_t(max_layers))
      s = {StatusCode::kLimitExceeded,
           strCat(layers, " material texture layers in one array (this context ",
                  "holds at most ", max_layers, " in a texture array)")};
  // Colour layers decode sRGB as they are sampled; data layers are linear. A character without
  // data images gets one 1 x 1 data layer, so the unit always holds a complete texture.
  if (table->data_layers.empty()) {
    Image flat;
    flat.width = flat.height = 1;
    flat.rgba8 = {128, 128, 255, 255};
    table->data_layers.push_back(flat);
  }
  if (s.isOk())
    s = uploadLayers(&base_texture, GL_SRGB8_ALPHA8, table->layers, table->width, table->height,
                     "the character's colour texture array");
  if (s.isOk())
    s = uploadLayers(&data_texture, GL_RGBA8, table->data_layers, table->data_width,
                     table->data_height, "the character's data texture array");
  return s;
}

void CharacterBuffers::bindMaterials() const {
  glBindTextureUnit(1, base_texture);
  glBindTextureUnit(4, data_texture);
  if (esProfile()) {  // The indices are vertex attribute 6 there (describeVertexFormat).
    glBindBufferBase(GL_UNIFORM_BUFFER, 11, material_table);
    return;
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, vertex_materials);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, material_table);
}

void CharacterBuffers::describeVertexFormat(GLuint v) const {
  glVertexArrayVertexBuffer(v, 0, vertex_buffer, 0, GLsizei(stride_bytes));
  glVertexArrayElementBuffer(v, index_buffer);
  for (GLuint loc = 0; loc < 5; ++loc) {
    glEnableVertexArrayAttrib(v, loc);
    glVertexArrayAttribBinding(v, loc, 0);
  }
  glVertexArrayAttribFormat(v, 0, 3, GL_FLOAT, GL_FALSE, VertexStream::kPositionOffset);
  glVertexArrayAttribFormat(v, 1, 4, GL_INT_2_10_10_10_REV, GL_TRUE, VertexStream::kNormalOffset);
  glVertexArrayAttribFormat(v, 2, 2, GL_HALF_FLOAT, GL_FALSE, VertexStream::kTexcoordOffset);
  glVertexArrayAttribIFormat(v, 3, 4, wide_joints ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE,
                             VertexStream::kJointsOffset);
  glVertexArrayAttribFormat(v, 4, 4, GL_UNSIGNED_SHORT, GL_TRUE, wide_joints ? 28 : 24);
  // The tangent (attribute 7); without tangents the normal's bits, whose w is 0: the shaders
  // read w == 0 as "no tangent frame" (nothing read from the host's generic attribute state).
  glEnableVertexArrayAttrib(v, 7);
  glVertexArrayAttribBinding(v, 7, 0);
  glVertexArrayAttribFormat(v, 7, 4, GL_INT_2_10_10_10_REV, GL_TRUE,
                            tangent_offset != 0 ? tangent_offset : VertexStream::kNormalOffset);
  // Texture coordinates 1 (attribute 8) and the colour (9); without them other words of the
  // vertex, which the fragment stage does not read (SiMaterial.layer.w says what the mesh has).
  for (GLuint loc : {8u, 9u}) {
    glEnableVertexArrayAttrib(v, loc);
    glVertexArrayAttribBinding(v, loc, 0);
  }
  glVertexArrayAttribFormat(
      v, 8, 2, GL_HALF_FLOAT, GL_FALSE,
      texcoord1_offset != 0 ? texcoord1_offset : VertexStream::kTexcoordOffset);
  glVertexArrayAttribFormat(v, 9, 4, GL_UNSIGNED_BYTE, GL_TRUE,
                            color_offset != 0 ? color_offset : VertexStream::kNormalOffset);
  if (joints1_offset != 0) {  // Influences 5 to 8 (attributes 10 and 11): SI_EIGHT_INFLUENCES.
    for (GLuint loc : {10u, 11u}) {
      glEnableVertexArrayAttrib(v, loc);
      glVertexArrayAttribBinding(v, loc, 0);
    }
    glVertexArrayAttribIFormat(v, 10, 4, wide_joints ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE,
                               joints1_offset);
    glVertexArrayAttribFormat(v, 11, 4, GL_UNSIGNED_SHORT, GL_TRUE, weights1_offset);
  }
  if (morph_offset != 0) {  // The morph word (attribute 12): SI_MORPH_TARGETS.
    glEnableVertexArrayAttrib(v, 12);
    glVertexArrayAttribBinding(v, 12, 0);
    glVertexArrayAttribIFormat(v, 12, 1, GL_UNSIGNED_INT, morph_offset);
  }
  if (esProfile()) {  // GLSL ES 3.00 reads each vertex's material index as attribute 6.
    glVertexArrayVertexBuffer(v, 1, vertex_materials, 0, 2);
    glEnableVertexArrayAttrib(v, 6);
    glVertexArrayAttribBinding(v, 6, 1);
    glVertexArrayAttribIFormat(v, 6, 1, GL_UNSIGNED_SHORT, 0);
  }
}

void CharacterBuffers::release() {
  if (vao != kNoObject) glDeleteVertexArrays(1, &vao);
  const GLuint buffers[] = {vertex_buffer, index_buffer, vertex_materials, material_table};
  glDeleteBuffers(4, buffers);
  const GLuint textures[] = {base_texture, data_texture, morph_texture};
  glDeleteTextures(3, textures);
  vao = vertex_buffer = index_buffer = base_texture = data_texture = vertex_materials =
      material_table = morph_texture = kNoObject;
}

}  // namespace si::detail
