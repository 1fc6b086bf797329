// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The compacted vertex lists of pre-skinning.
#include "gl/resources/preskin_lists.h"

#include <algorithm>

#include "gl/resources/gl_allocation.h"

namespace si::detail {

Status PreSkinLists::build(const CharacterBuffers& character) {
  const SkinnedMesh& mesh = character.mesh;
  std::vector<uint32_t> lod_vertices, local_indices, local(mesh.vertexCount(), UINT32_MAX);
  std::vector<std::vector<Lod>> built(mesh.sub_meshes.size());
  uint32_t largest = 0;
  for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm)
    for (const IndexRange& range : mesh.sub_meshes[sm].lods) {
      Lod l;
      l.first_index = uint32_t(local_indices.size());
      l.index_count = range.index_count;
      l.vertex_offset = uint32_t(lod_vertices.size());
      std::vector<uint32_t> used(mesh.indices.begin() + range.first_index,
                                 mesh.indices.begin() + range.first_index + range.index_count);
      std::sort(used.begin(), used.end());
      used.erase(std::unique(used.begin(), used.end()), used.end());
      for (size_t k = 0; k < used.size(); ++k) local[used[k]] = uint32_t(k);
      lod_vertices.insert(lod_vertices.end(), used.begin(), used.end());
      for (uint32_t i = range.first_index; i < range.first_index + range.index_count; ++i)
        local_indices.push_back(local[mesh.indices[i]]);
      l.vertex_count = uint32_t(used.size());
      largest = std::max(largest, l.vertex_count);
      built[sm].push_back(l);
    }
  lod_vertices.push_back(0);  // Never empty (a zero-sized buffer is an error).
  local_indices.push_back(0);
  Status s = createBuffer(&lod_vertex_list, lod_vertices.size() * 4, lod_vertices.data(), 0,
                          "pre-skinning: the LOD vertex lists");
  if (s.isOk())
    s = createBuffer(&index_buffer, local_indices.size() * 4, local_indices.data(), 0,
                     "pre-skinning: the re-indexed triangles");
  if (!s.isOk()) return s;
  lods = std::move(built);
  max_lod_vertices = largest;
  source_words = character.stride_bytes / 4 | (character.wide_joints ? 0x100u : 0u) |
                 (character.texcoord1_offset != 0 ? 0x400u : 0u) |
                 (character.color_offset != 0 ? 0x800u : 0u) |
                 (character.joints1_offset != 0 ? 0x1000u : 0u) |
                 (character.morph_offset != 0 ? 0x2000u : 0u);
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
