// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A mesh's morph target entries grouped by vertex (then by target): the order the shaders' morph
// stream holds them in (si::buildMorphStream, the vertex stream's morph word), which the bake's
// measurement of morphed vertices and the CPU path read too.
#include <cstdint>
#include <vector>

#include "si/core/skinned_mesh.h"

namespace si::detail {

struct MorphEntriesByVertex {
  struct Entry {
    uint32_t target = 0;  ///< Index in SkinnedMesh::morph_targets.
    uint32_t index = 0;   ///< Index in that target's vertices and deltas.
  };
  /// Vertex v's entries are entries[first[v] .. first[v + 1]); vertexCount() + 1 offsets.
  std::vector<uint32_t> first;
  std::vector<Entry> entries;
};

/// The entries of `mesh`'s morph targets (which must validate) by vertex, then target.
inline MorphEntriesByVertex morphEntriesByVertex(const SkinnedMesh& mesh) {
  MorphEntriesByVertex out;
  out.first.assign(mesh.vertexCount() + 1, 0u);
  for (const MorphTarget& t : mesh.morph_targets)
    for (uint32_t v : t.vertices) ++out.first[v + 1];
  for (size_t v = 1; v < out.first.size(); ++v) out.first[v] += out.first[v - 1];
  out.entries.resize(out.first.back());
  std::vector<uint32_t> next(out.first.begin(), out.first.end() - 1);
  for (size_t t = 0; t < mesh.morph_targets.size(); ++t)
    for (size_t i = 0; i < mesh.morph_targets[t].vertices.size(); ++i)
      out.entries[next[mesh.morph_targets[t].vertices[i]]++] = {uint32_t(t), uint32_t(i)};
  return out;
}

}  // namespace si::detail
