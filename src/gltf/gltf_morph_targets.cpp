// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Morph targets (glTF 2.0 specification, "Morph Targets"): each node's mesh targets become the
// character's (SkinnedMesh::morph_targets), named by the mesh's extras.targetNames, weighted by
// the node's or mesh's default weights; each primitive's POSITION, NORMAL and TANGENT deltas
// are read densely, moved as the primitive's surface is (a rigid part) and kept sparsely (the
// vertices a target moves). The weights channels that animate them: gltf_animation.cpp.
#include <algorithm>
#include <cmath>

#include "gltf/gltf_convert.h"

namespace si::detail {

Status beginNodeMorphTargets(const tinygltf::Model& m, size_t node, const std::string& where,
                             Character* c, NodeMorphTargets* out) {
  const tinygltf::Node& n = m.nodes[node];
  const tinygltf::Mesh& mesh = m.meshes[size_t(n.mesh)];
  const size_t count = mesh.primitives.empty() ? 0 : mesh.primitives.front().targets.size();
  for (size_t p = 1; p < mesh.primitives.size(); ++p)
    if (mesh.primitives[p].targets.size() != count)
      return corrupt(strCat(where, ": primitive ", p, " has ", mesh.primitives[p].targets.size(),
                            " morph targets and primitive 0 ", count,
                            " (glTF: every primitive the same)"));
  *out = NodeMorphTargets{uint32_t(c->mesh.morph_targets.size()), uint32_t(count)};
  if (count == 0) return Status::ok();
  if (c->mesh.morph_targets.size() + count > kMaxMorphTargets)
    return {StatusCode::kLimitExceeded, strCat("glTF: ", where, " would take the character past ",
                                               kMaxMorphTargets, " morph targets")};
  // The node's weights win over the mesh's (glTF "Morph Targets"); both default to 0.
  const std::vector<double>& weights = !n.weights.empty() ? n.weights : mesh.weights;
  if (!weights.empty() && weights.size() != count)
    return corrupt(
        strCat(where, ": ", weights.size(), " default weights for ", count, " morph targets"));
  // extras is any JSON (tinygltf asserts on a key of a non-object).
  const tinygltf::Value none;
  const tinygltf::Value& names = mesh.extras.IsObject() && mesh.extras.Has("targetNames")
                                     ? mesh.extras.Get("targetNames")
                                     : none;
  for (size_t k = 0; k < count; ++k) {
    MorphTarget t;
    const bool named = names.IsArray() && names.ArrayLen() == count &&
                       names.Get(int(k)).IsString() &&
                       !names.Get(int(k)).Get<std::string>().empty();
    t.name = named ? names.Get(int(k)).Get<std::string>() : strCat(where, " target ", k);
    t.default_weight = weights.empty() ? 0.0f : float(weights[k]);
    if (!std::isfinite(t.default_weight))
      return corrupt(strCat(where, ": default weight ", k, " is not finite"));
    c->mesh.morph_targets.push_back(std::move(t));
  }
  return Status::ok();
}

Status readPrimitiveMorphDeltas(const tinygltf::Model& m, const tinygltf::Primitive& prim,
                                const std::string& where, size_t vertex_count,
                                std::vector<PrimitiveMorphDeltas>* out) {
  out->assign(prim.targets.size(), PrimitiveMorphDeltas());
  for (size_t k = 0; k < prim.targets.size(); ++k) {
    const std::map<std::string, int>& target = prim.targets[k];
    const auto read = [&](const char* key, std::vector<glm::vec3>* deltas) -> Status {
      const auto it = target.find(key);
      if (it == target.end()) return Status::ok();
      const std::string what = strCat(where, " morph target ", k, " ", key);
      std::vector<double> v;
      const Status s =
          readAccessor(m, it->second, {TINYGLTF_TYPE_VEC3}, kFloatOrNormalized, what, &v);
      if (!s.isOk()) return s;
      if (v.size() != vertex_count * 3)
        return corrupt(
            strCat(what, " has ", v.size() / 3, " elements for ", vertex_count, " positions"));
      for (size_t i = 0; i < vertex_count; ++i)
        deltas->push_back(glm::vec3(float(v[i * 3]), float(v[i * 3 + 1]), float(v[i * 3 + 2])));
      return Status::ok();
    };
    PrimitiveMorphDeltas& d = (*out)[k];
    Status s = read("POSITION", &d.positions);
    if (s.isOk()) s = read("NORMAL", &d.normals);
    if (s.isOk()) s = read("TANGENT", &d.tangents);
    if (!s.isOk()) return s;
  }
  return Status::ok();
}

void placeMorphDeltas(const glm::dmat4& rest, const PrimitiveSurface& unplaced,
                      std::vector<PrimitiveMorphDeltas>* deltas) {
  // placeSurface gives normalize(N n) and normalize(L t): a delta d moves them to
  // normalize(N (n + d)) and normalize(L (t + d)), the placed ones plus N d / |N n| and
  // L d / |L t|, so the morphed and renormalized results stay exact.
  const glm::dmat3 linear(rest);
  const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
  const auto scaled = [](const glm::dmat3& a, const glm::vec3& base, const glm::vec3& d) {
    const double len = glm::length(a * glm::dvec3(base));
    return len > 0.0 && std::isfinite(len) ? glm::vec3(a * glm::dvec3(d) / len) : glm::vec3(0.0f);
  };
  for (PrimitiveMorphDeltas& d : *deltas) {
    for (glm::vec3& p : d.positions) p = glm::vec3(linear * glm::dvec3(p));
    for (size_t i = 0; i < d.normals.size() && i < unplaced.normals.size(); ++i)
      d.normals[i] = scaled(normal_matrix, unplaced.normals[i], d.normals[i]);
    for (size_t i = 0; i < d.tangents.size() && i < unplaced.tangents.size(); ++i)
      d.tangents[i] = scaled(linear, glm::vec3(unplaced.tangents[i]), d.tangents[i]);
  }
}

void appendMorphDeltas(const std::vector<PrimitiveMorphDeltas>& deltas, uint32_t first_vertex,
                       const NodeMorphTargets& range, Character* c) {
  const glm::vec3 zero(0.0f);
  for (size_t k = 0; k < deltas.size() && k < range.count; ++k) {
    const PrimitiveMorphDeltas& d = deltas[k];
    MorphTarget& t = c->mesh.morph_targets[range.first + k];
    const size_t n = std::max({d.positions.size(), d.normals.size(), d.tangents.size()});
    for (size_t i = 0; i < n; ++i) {
      const glm::vec3 p = i < d.positions.size() ? d.positions[i] : zero;
      const glm::vec3 nd = i < d.normals.size() ? d.normals[i] : zero;
      const glm::vec3 td = i < d.tangents.size() ? d.tangents[i] : zero;
      if (p == zero && nd == zero && td == zero) continue;  // Sparse: moved vertices only.
      t.vertices.push_back(first_vertex + uint32_t(i));
      t.position_deltas.push_back(p);
      t.normal_deltas.push_back(nd);
      t.tangent_deltas.push_back(td);
    }
  }
}

void finishMorphTargets(GltfImportReport* report, Character* c) {
  const glm::vec3 zero(0.0f);
  const auto all_zero = [&](const std::vector<glm::vec3>& v) {
    return std::all_of(v.begin(), v.end(), [&](const glm::vec3& d) { return d == zero; });
  };
  for (MorphTarget& t : c->mesh.morph_targets) {
    if (all_zero(t.normal_deltas)) t.normal_deltas.clear();
    if (all_zero(t.tangent_deltas)) t.tangent_deltas.clear();
    if (!t.tangent_deltas.empty() && c->mesh.tangents.empty()) {
      report->warnings.push_back(
          strCat("morph target '", t.name, "': TANGENT deltas dropped with the mesh's tangents"));
      t.tangent_deltas.clear();
    }
    report->morph_target_entries += t.vertices.size();
  }
  report->morph_targets = uint32_t(c->mesh.morph_targets.size());
}

}  // namespace si::detail
