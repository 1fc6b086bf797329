// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The compacted vertex lists of pre-skinning.
#include "gl/resources/preskin_lists.h"

#include "gl/resources/gl_allocation.h"

namespace si::detail {

Status PreSkinLists::build(const CharacterBuffers& character) {
  PreSkinListData d;
  buildPreSkinLists(character.mesh, &d);
  Status s = createBuffer(&lod_vertex_list, d.lod_vertices.size() * 4, d.lod_vertices.data(), 0,
                          "pre-skinning: the LOD vertex lists");
  if (s.isOk())
    s = createBuffer(&index_buffer, d.local_indices.size() * 4, d.local_indices.data(), 0,
                     "pre-skinning: the re-indexed triangles");
  if (!s.isOk()) return s;
  lods = std::move(d.lods);
  max_lod_vertices = d.max_lod_vertices;
  VertexStream layout;  // The uploaded stream's layout (its bytes are on the GPU).
  layout.stride_bytes = character.stride_bytes;
  layout.wide_joints = character.wide_joints;
  layout.texcoord1_offset = character.texcoord1_offset;
  layout.color_offset = character.color_offset;
  layout.joints1_offset = character.joints1_offset;
  layout.morph_offset = character.morph_offset;
  source_words = preSkinSourceWords(layout);
  tangents = character.tangent_offset != 0;
  return Status::ok();
}

void PreSkinLists::release() {
  const GLuint buffers[] = {index_buffer, lod_vertex_list};
  glDeleteBuffers(2, buffers);
  index_buffer = lod_vertex_list = kNoObject;
  lods.clear();
}

}  // namespace si::detail
