// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "bake/morph_measurement.h"

namespace si::detail {

MorphedSlots::MorphedSlots(const SkinnedMesh& mesh, const SkinnedMesh& gpu_mesh,
                           const InfluenceGroups& groups)
    : mesh_(mesh), gpu_mesh_(gpu_mesh) {
  if (mesh.morph_targets.empty()) return;
  // Each vertex's entries, gathered target by target.
  std::vector<std::vector<Entry>> per_vertex(mesh.vertexCount());
  for (size_t t = 0; t < mesh.morph_targets.size(); ++t) {
    const MorphTarget& target = mesh.morph_targets[t];
    for (size_t i = 0; i < target.vertices.size(); ++i)
      per_vertex[target.vertices[i]].push_back({uint32_t(t), target.position_deltas[i]});
  }
  for (size_t slot = 0; slot < groups.size(); ++slot) {
    const uint32_t v = groups.vertex(slot);
    if (per_vertex[v].empty()) continue;
    vertices_.push_back(
        {uint32_t(slot), v, uint32_t(entries_.size()), uint32_t(per_vertex[v].size())});
    entries_.insert(entries_.end(), per_vertex[v].begin(), per_vertex[v].end());
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
