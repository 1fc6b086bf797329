// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The compacted vertex lists of pre-skinning.
#include "core/pre_skin_lists.h"

#include <algorithm>

namespace si::detail {

void buildPreSkinLists(const SkinnedMesh& mesh, PreSkinListData* out) {
  PreSkinListData d;
  std::vector<uint32_t> local(mesh.vertexCount(), UINT32_MAX);
  d.lods.resize(mesh.sub_meshes.size());
  for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm)
    for (const IndexRange& range : mesh.sub_meshes[sm].lods) {
      PreSkinLod l;
      l.first_index = uint32_t(d.local_indices.size());
      l.index_count = range.index_count;
      l.vertex_offset = uint32_t(d.lod_vertices.size());
      std::vector<uint32_t> used(mesh.indices.begin() + range.first_index,
                                 mesh.indices.begin() + range.first_index + range.index_count);
      std::sort(used.begin(), used.end());
      used.erase(std::unique(used.begin(), used.end()), used.end());
      for (size_t k = 0; k < used.size(); ++k) local[used[k]] = uint32_t(k);
      d.lod_vertices.insert(d.lod_vertices.end(), used.begin(), used.end());
      for (uint32_t i = range.first_index; i < range.first_index + range.index_count; ++i)
        d.local_indices.push_back(local[mesh.indices[i]]);
      l.vertex_count = uint32_t(used.size());
      d.max_lod_vertices = std::max(d.max_lod_vertices, l.vertex_count);
      d.lods[sm].push_back(l);
    }
  d.lod_vertices.push_back(0);  // Never empty (a zero-sized buffer is an error).
  d.local_indices.push_back(0);
  *out = std::move(d);
}

uint32_t preSkinSourceWords(const VertexStream& stream) {
  return stream.stride_bytes / 4 | (stream.wide_joints ? 0x100u : 0u) |
         (stream.texcoord1_offset != 0 ? 0x400u : 0u) | (stream.color_offset != 0 ? 0x800u : 0u) |
         (stream.joints1_offset != 0 ? 0x1000u : 0u) | (stream.morph_offset != 0 ? 0x2000u : 0u);
}

}  // namespace si::detail
