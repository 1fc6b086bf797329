// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A mesh's morph target entries grouped by vertex (then by target), which the bake's measurement
// of morphed vertices reads; and each vertex's run ordered by effect, largest first, with the
// bound on what the rest of the run can move the vertex: the order the shaders' morph stream
// holds them in (si::buildMorphStream, the vertex stream's morph word), so a coarse LOD stops
// where the rest moves the vertex less than its cut (si::morphLodCuts), as the CPU path does.
#include <cstdint>
#include <cstring>
#include <vector>

#include "si/core/baked_palette.h"
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

/// Per morph target of `palette`, the largest |weight| a draw can give it: the largest stored in
/// any frame (border frames too), x 1.25 where a clip interpolates cubically (Catmull-Rom's four
/// weights sum to at most 1.25 in absolute value, in every interval mode); a crossfade mixes
/// two such weights. Empty for a palette without targets.
std::vector<float> morphWeightBounds(const BakedPalette& palette);

/// The stored form of a tail bound (MorphStream's entry word, bits 16 to 31): the float's upper
/// 16 bits, rounded up (towards +infinity) so what the shader reads is never below the bound.
uint32_t morphTailBits(float tail);
/// The tail bound an entry word carries (its bits 16 to 31 as the upper bits of a float).
inline float morphTailOfWord(uint32_t word) {
  const uint32_t bits = word & 0xFFFF0000u;
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

/// Orders each vertex's run of `by_vertex` (of `mesh`) by effect, largest first: an entry's
/// effect is |position delta| x its target's weight bound (`weight_bounds`, one per target),
/// ties by target. Returns, per entry in the new order, its tail: the sum of the effects from it
/// to the end of its run (the farthest those entries can move the vertex), rounded up as the
/// stream stores it (morphTailOfWord(morphTailBits(tail))). Non-increasing along a run.
std::vector<float> orderMorphEntriesByEffect(const SkinnedMesh& mesh,
                                             const std::vector<float>& weight_bounds,
                                             MorphEntriesByVertex* by_vertex);

}  // namespace si::detail
