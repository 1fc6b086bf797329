// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The baker's measurement of morphed vertices: the error kernel (InfluenceGroups) keeps each
// vertex's bind position fixed, so the vertices morph targets move are measured again here,
// with the targets added at the reference's weights and at the shader's (interpolated from
// the palette), and their errors and positions replaced.
#include <cstdint>
#include <vector>

#include "bake/error_kernel.h"
#include "si/core/skinned_mesh.h"
#include "si/core/span.h"

namespace si::detail {

class MorphedSlots {
 public:
  /// The slots of `groups` whose vertex some target of `mesh` moves. `mesh` holds the source
  /// weights, `gpu_mesh` the same vertices with the stored weights (as InfluenceGroups takes
  /// them); both must outlive this.
  MorphedSlots(const SkinnedMesh& mesh, const SkinnedMesh& gpu_mesh, const InfluenceGroups& groups);

  bool empty() const { return vertices_.empty(); }

  /// Replaces (*errors)[slot] of each morphed vertex by |shader - reference|: the shader skins
  /// the vertex with its targets at `emulated_weights` by `emulated` and the stored weights, the
  /// reference with its targets at `reference_weights` by `reference` and the source's (in
  /// double).
  void patchErrors(Span<const glm::mat4> emulated, Span<const float> emulated_weights,
                   Span<const glm::dmat4> reference, Span<const double> reference_weights,
                   std::vector<float>* errors) const;
  /// Replaces (*positions)[slot] of each morphed vertex by the shader's position.
  void patchPositions(Span<const glm::mat4> emulated, Span<const float> emulated_weights,
                      std::vector<glm::vec3>* positions) const;

 private:
  struct Entry {
    uint32_t target = 0;
    glm::vec3 delta{0.0f};
  };
  struct Vertex {
    uint32_t slot = 0, vertex = 0, first_entry = 0, entry_count = 0;
  };
  template <typename W>
  glm::dvec3 morphed(const Vertex& v, Span<const W> weights) const;

  const SkinnedMesh& mesh_;
  const SkinnedMesh& gpu_mesh_;
  std::vector<Vertex> vertices_;
  std::vector<Entry> entries_;
};

}  // namespace si::detail
