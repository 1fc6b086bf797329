// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Uploading the character: vertex stream, indices, vertex format, base colour texture.
#include "gl/resources/character_buffers.h"

#include <algorithm>
#include <cmath>

#include "core/str_cat.h"
#include "gl/profile/gl_profile.h"
#include "gl/programs/program_catalog.h"
#include "gl/resources/gl_allocation.h"
#include "si/core/material_table.h"
#include "si/core/shader_inputs.h"

namespace si::detail {

Status CharacterBuffers::upload(const Character& character, const BakedPalette& palette,
                                uint32_t max_texture_size) {
  const SkinnedMesh& m = character.mesh;
  Status s = m.validate(character.skeleton.jointCount());
  if (!s.isOk()) return s;
  if (palette.skeleton_to_palette.size() != character.skeleton.jointCount())
    return {StatusCode::kInvalidArgument,
            "the palette was baked for another skeleton"};
  VertexStream stream;
  s = buildVertexStream(m, palette, &stream);
  if (!s.isOk()) return s;
  release();
  s = createBuffer(&vertex_buffer, stream.bytes.size(), stream.bytes.data(), 0,
                   "the character's vertex buffer");
  if (s.isOk())
    s = createIndexBuffer(&index_buffer, m.indices.size() * 4, m.indices.data(),
                          "the character's index buffer");
  if (!s.isOk()) {
    release();
    return s;
  }
  wide_joints = stream.wide_joints;
  stride_bytes = stream.stride_bytes;
  sub_meshes = m.sub_meshes;
  vertex_count = uint32_t(m.vertexCount());
  mesh = m;

  // Materials: the table, each vertex's index (16 bits, two a word), the texture array.
  MaterialTable table;
  s = buildMaterialTable(character, max_texture_size, &table);
  std::vector<uint32_t> words((table.vertex_materials.size() + 1) / 2, 0);
  for (size_t v = 0; v < table.vertex_materials.size(); ++v)
    words[v / 2] |= uint32_t(table.vertex_materials[v]) << ((v % 2) * 16);
  struct GpuMaterial {
    glm::vec4 factor;
    glm::uvec4 layer;
  };
  std::vector<GpuMaterial> entries;
  for (const MaterialEntry& e : table.materials)
    entries.push_back({e.base_color_factor, glm::uvec4(e.layer, 0, 0, 0)});
  if (s.isOk() && esProfile()) {
    // A uniform block of kEsMaxMaterials entries there; the bound buffer holds it whole (WebGL 2
    // refuses a draw whose uniform buffer is smaller than its block).
    if (entries.size() > kEsMaxMaterials)
      s = {StatusCode::kLimitExceeded,
           strCat(entries.size(), " materials (the OpenGL ES profile's material block holds ",
                  kEsMaxMaterials, ")")};
    entries.resize(kEsMaxMaterials, GpuMaterial{glm::vec4(1.0f), glm::uvec4(0)});
  }
  if (s.isOk())
    s = createBuffer(&vertex_materials, words.size() * 4, words.data(), 0,
                     "the character's per-vertex materials");
  if (s.isOk())
    s = createBuffer(&material_table, entries.size() * sizeof(GpuMaterial), entries.data(), 0,
                     "the character's material table");
  GLint max_layers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
  if (s.isOk() && table.layers.size() > size_t(max_layers))
    s = {StatusCode::kLimitExceeded,
         strCat(table.layers.size(), " base colour layers (this context ",
                "holds at most ", max_layers, " in a texture array)")};
  const GLsizei w = GLsizei(table.width), h = GLsizei(table.height);
  const GLsizei levels = GLsizei(std::floor(std::log2(double(std::max(w, h))))) + 1;
  if (s.isOk())
    s = createTexture2DArray(&base_texture, levels, GL_RGBA8, w, h, GLsizei(table.layers.size()),
                             "the character's base colour texture array");
  if (!s.isOk()) {
    release();
    return s;
  }
  glCreateVertexArrays(1, &vao);
  describeVertexFormat(vao);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (size_t l = 0; l < table.layers.size(); ++l)
    glTextureSubImage3D(base_texture, 0, 0, 0, GLint(l), w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                        table.layers[l].rgba8.data());
  glGenerateTextureMipmap(base_texture);
  glTextureParameteri(base_texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(base_texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return Status::ok();
}

void CharacterBuffers::bindMaterials() const {
  glBindTextureUnit(1, base_texture);
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
  if (base_texture != kNoObject) glDeleteTextures(1, &base_texture);
  vao = vertex_buffer = index_buffer = base_texture = vertex_materials = material_table = kNoObject;
}

}  // namespace si::detail
