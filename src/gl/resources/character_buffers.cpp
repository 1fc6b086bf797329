// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Uploading the character: vertex stream, indices, vertex format, base colour texture.
#include "gl/resources/character_buffers.h"

#include <algorithm>
#include <cmath>

#include "gl/resources/gl_allocation.h"
#include "si/core/shader_inputs.h"

namespace si::detail {

Status CharacterBuffers::upload(const Character& character, const BakedPalette& palette) {
  const SkinnedMesh& m = character.mesh;
  Status s = m.validate(character.skeleton.jointCount());
  if (!s.isOk()) return s;
  if (palette.skeleton_to_palette.size() != character.skeleton.jointCount())
    return {StatusCode::kInvalidArgument,
            "uploadCharacter: the palette was baked for another skeleton"};
  VertexStream stream;
  s = buildVertexStream(m, palette, &stream);
  if (!s.isOk()) return {s.code(), "uploadCharacter: " + s.message()};
  release();
  s = createBuffer(&vertex_buffer, stream.bytes.size(), stream.bytes.data(), 0,
                   "uploadCharacter: the vertex buffer");
  if (s.isOk())
    s = createBuffer(&index_buffer, m.indices.size() * 4, m.indices.data(), 0,
                     "uploadCharacter: the index buffer");
  if (!s.isOk()) {
    release();
    return s;
  }
  wide_joints = stream.wide_joints;
  stride_bytes = stream.stride_bytes;
  glCreateVertexArrays(1, &vao);
  describeVertexFormat(vao);
  sub_meshes = m.sub_meshes;
  vertex_count = uint32_t(m.vertexCount());
  mesh = m;

  // Base colour: the first material's factor and image; white (alpha 1: tint everywhere) if none.
  base_factor = character.materials.empty() ? glm::vec4(1.0f)
                                            : character.materials[0].base_color_factor;
  const Image* image = nullptr;
  if (!character.materials.empty() && character.materials[0].base_color_image >= 0)
    image = &character.images[size_t(character.materials[0].base_color_image)];
  const uint8_t white[4] = {255, 255, 255, 255};
  const GLsizei w = image ? GLsizei(image->width) : 1, h = image ? GLsizei(image->height) : 1;
  const GLsizei levels = GLsizei(std::floor(std::log2(double(std::max(w, h))))) + 1;
  s = createTexture2D(&base_texture, levels, GL_RGBA8, w, h,
                      "uploadCharacter: the base colour texture");
  if (!s.isOk()) {
    release();
    return s;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(base_texture, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE,
                      image ? image->rgba8.data() : white);
  glGenerateTextureMipmap(base_texture);
  glTextureParameteri(base_texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(base_texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return Status::ok();
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
}

void CharacterBuffers::release() {
  if (vao != kNoObject) glDeleteVertexArrays(1, &vao);
  const GLuint buffers[] = {vertex_buffer, index_buffer};
  glDeleteBuffers(2, buffers);
  if (base_texture != kNoObject) glDeleteTextures(1, &base_texture);
  vao = vertex_buffer = index_buffer = base_texture = kNoObject;
}

}  // namespace si::detail
