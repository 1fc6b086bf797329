// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What pre-skinning needs of a mesh, for every back-end: for each (sub-mesh, LOD), the compacted
// list of the vertices its triangles use and its triangles re-indexed to that list, so a compute
// pass skins exactly what is drawn (pre_skin_common.glsl's lists); and the source vertex's
// layout word the passes read it by. No GPU here: si::gl's PreSkinLists and si::vk upload them.

#include <cstdint>
#include <vector>

#include "si/core/shader_inputs.h"
#include "si/core/skinned_mesh.h"

namespace si::detail {

/// One (sub-mesh, LOD)'s lists.
struct PreSkinLod {
  uint32_t first_index = 0, index_count = 0;     ///< Into local_indices.
  uint32_t vertex_offset = 0, vertex_count = 0;  ///< Into lod_vertices.
};

struct PreSkinListData {
  std::vector<std::vector<PreSkinLod>> lods;  ///< [sub_mesh][lod]
  /// Source vertex of each local vertex, every (sub-mesh, LOD) after another (never empty).
  std::vector<uint32_t> lod_vertices;
  /// The triangles re-indexed to their list, every (sub-mesh, LOD) after another (never empty).
  std::vector<uint32_t> local_indices;
  uint32_t max_lod_vertices = 0;  ///< The largest list.

  /// The lists of `sub_mesh` at `level` (its last LOD when `level` is past it).
  const PreSkinLod& lod(uint32_t sub_mesh, uint32_t level) const {
    const std::vector<PreSkinLod>& l = lods[sub_mesh];
    return l[level < l.size() ? level : l.size() - 1];
  }
};

/// Builds `mesh`'s lists (its indices, as validated by the back-end's upload).
void buildPreSkinLists(const SkinnedMesh& mesh, PreSkinListData* out);

/// pre_skin_common.glsl's u_layout.y for passes that write no tangents: 32-bit words per source
/// vertex of `stream` (stride / 4), | 0x100 with wide joints, | 0x400 with texture coordinates
/// 1, | 0x800 with colours, | 0x1000 with 8 influences, | 0x2000 with morph targets.
uint32_t preSkinSourceWords(const VertexStream& stream);

}  // namespace si::detail
