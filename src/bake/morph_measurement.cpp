// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "bake/morph_measurement.h"

#include "core/morph_entries.h"

namespace si::detail {

MorphedSlots::MorphedSlots(const SkinnedMesh& mesh, const SkinnedMesh& gpu_mesh,
                           const InfluenceGroups& groups)
    : mesh_(mesh), gpu_mesh_(gpu_mesh) {
  if (mesh.morph_targets.empty()) return;
  const MorphEntriesByVertex by_vertex = morphEntriesByVertex(mesh);
  for (size_t slot = 0; slot < groups.size(); ++slot) {
    const uint32_t v = groups.vertex(slot);
    const uint32_t begin = by_vertex.first[v], end = by_vertex.first[v + 1];
    if (begin == end) continue;
    vertices_.push_back({uint32_t(slot), v, uint32_t(entries_.size()), end - begin});
    for (uint32_t e = begin; e < end; ++e) {
      const MorphEntriesByVertex::Entry& entry = by_vertex.entries[e];
      entries_.push_back(
          {entry.target, mesh.morph_targets[entry.target].position_deltas[entry.index]});
    }
  }
}

template <typename W>
glm::dvec3 MorphedSlots::morphed(const Vertex& v, Span<const W> weights) const {
  glm::dvec3 p(mesh_.positions[v.vertex]);
  for (uint32_t e = v.first_entry; e < v.first_entry + v.entry_count; ++e)
    p += double(weights[entries_[e].target]) * glm::dvec3(entries_[e].delta);
  return p;
}

void MorphedSlots::patchErrors(Span<const glm::mat4> emulated, Span<const float> emulated_weights,
                               Span<const glm::dmat4> reference,
                               Span<const double> reference_weights,
                               std::vector<float>* errors) const {
  const size_t influences = mesh_.influenceCount();
  for (const Vertex& v : vertices_) {
    const glm::dvec4 pe(morphed(v, emulated_weights), 1.0), pr(morphed(v, reference_weights), 1.0);
    glm::dvec3 shader(0.0), exact(0.0);
    for (size_t k = 0; k < influences; ++k) {
      const Influence stored = gpu_mesh_.influence(v.vertex, k),
                      source = mesh_.influence(v.vertex, k);
      if (stored.weight != 0.0f)
        shader += double(stored.weight) * glm::dvec3(glm::dmat4(emulated[stored.joint]) * pe);
      if (source.weight != 0.0f)
        exact += double(source.weight) * glm::dvec3(reference[source.joint] * pr);
    }
    (*errors)[v.slot] = float(glm::length(shader - exact));
  }
}

void MorphedSlots::patchPositions(Span<const glm::mat4> emulated,
                                  Span<const float> emulated_weights,
                                  std::vector<glm::vec3>* positions) const {
  const size_t influences = gpu_mesh_.influenceCount();
  for (const Vertex& v : vertices_) {
    const glm::dvec4 p(morphed(v, emulated_weights), 1.0);
    glm::dvec3 shader(0.0);
    for (size_t k = 0; k < influences; ++k) {
      const Influence stored = gpu_mesh_.influence(v.vertex, k);
      if (stored.weight != 0.0f)
        shader += double(stored.weight) * glm::dvec3(glm::dmat4(emulated[stored.joint]) * p);
    }
    (*positions)[v.slot] = glm::vec3(shader);
  }
}

}  // namespace si::detail
