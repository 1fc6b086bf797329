// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What pre-skinning needs of the character (core/pre_skin_lists.h's lists, uploaded): for each
// (sub-mesh, LOD), the compacted list of the vertices its triangles use and its triangles
// re-indexed to that list, so a compute pass skins exactly what is drawn. Shared by the compute
// path and the GPU-driven path.

#include <glad/gl.h>

#include <vector>

#include "core/pre_skin_lists.h"
#include "gl/programs/program_set.h"
#include "gl/resources/character_buffers.h"

namespace si::detail {

struct PreSkinLists {
  /// Into index_buffer (local indices) and lod_vertex_list (core/pre_skin_lists.h).
  using Lod = PreSkinLod;

  /// Builds the lists of `character` (after its upload).
  Status build(const CharacterBuffers& character);
  void release();

  /// The lists of `sub_mesh` at `lod` (its last LOD when `lod` is past it).
  const Lod& lod(uint32_t sub_mesh, uint32_t level) const {
    const std::vector<Lod>& l = lods[sub_mesh];
    return l[std::min<size_t>(level, l.size() - 1)];
  }

  std::vector<std::vector<Lod>> lods;  ///< [sub_mesh][lod]
  GLuint index_buffer = kNoObject;     ///< Local indices of every (sub-mesh, LOD).
  GLuint lod_vertex_list = kNoObject;  ///< Source vertex of each local vertex.
  uint32_t max_lod_vertices = 0;       ///< The largest list.
  /// 32-bit words per source vertex (stride / 4), | 0x100 with wide joints, | 0x400 with
  /// texture coordinates 1, | 0x800 with colours, | 0x1000 with 8 influences, | 0x2000 with
  /// morph targets: pre_skin_common.glsl's u_layout.y for a pass
  /// that writes no tangents (captureSkinnedPositions).
  uint32_t source_words = 8;
  /// The source vertices have a tangent word (CharacterBuffers::tangent_offset).
  bool tangents = false;
  /// u_layout.y for the passes that pre-skin into, and draw from, the tangent ring beside the
  /// vertex ring (ScratchBuffers): source_words, | 0x200 when the source has tangents.
  uint32_t drawLayout() const { return source_words | (tangents ? 0x200u : 0u); }
};

}  // namespace si::detail
