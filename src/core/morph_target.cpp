// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Morph targets: their checks and the double-precision application before skinning (glTF 2.0,
// "Morph Targets"; the normal and tangent renormalized after the blend, as the seed "Efficient
// Animation" does for its blended vertex frames).
#include "si/core/morph_target.h"

#include <cmath>

#include "core/str_cat.h"
#include "si/core/transform.h"

namespace si {
using detail::strCat;

Status validateMorphTargets(const std::vector<MorphTarget>& targets, size_t vertex_count,
                            bool has_tangents) {
  if (targets.size() > kMaxMorphTargets)
    return {StatusCode::kLimitExceeded,
            strCat("mesh: has ", targets.size(), " morph targets; at most ", kMaxMorphTargets)};
  for (size_t t = 0; t < targets.size(); ++t) {
    const MorphTarget& m = targets[t];
    const std::string where = strCat("mesh: morph target ", t, m.name.empty() ? "" : " '", m.name,
                                     m.name.empty() ? "" : "'");
    const size_t n = m.vertices.size();
    const auto optional = [&](const char* what, size_t c) -> Status {
      if (c == n || c == 0) return Status::ok();
      return {StatusCode::kCountMismatch,
              strCat(where, ": ", what, " has ", c, " elements for ", n, " vertices (or none)")};
    };
    if (m.position_deltas.size() != n)
      return {StatusCode::kCountMismatch,
              strCat(where, ": position_deltas has ", m.position_deltas.size(), " elements for ", n,
                     " vertices")};
    for (Status s : {optional("normal_deltas", m.normal_deltas.size()),
                     optional("tangent_deltas", m.tangent_deltas.size())})
      if (!s.isOk()) return s;
    if (!m.tangent_deltas.empty() && !has_tangents)
      return {StatusCode::kCountMismatch,
              where + ": has tangent_deltas, but the mesh has no tangents"};
    if (!std::isfinite(m.default_weight))
      return {StatusCode::kNotFinite, where + ": default_weight is not finite"};
    for (size_t i = 0; i < n; ++i) {
      if (m.vertices[i] >= vertex_count)
        return {StatusCode::kOutOfRange, strCat(where, ": entry ", i, " names vertex ",
                                                m.vertices[i], " of ", vertex_count)};
      if (i > 0 && m.vertices[i] <= m.vertices[i - 1])
        return {StatusCode::kNotSorted,
                strCat(where, ": vertices not strictly increasing at entry ", i)};
      if (!isFinite(m.position_deltas[i]) ||
          (!m.normal_deltas.empty() && !isFinite(m.normal_deltas[i])) ||
          (!m.tangent_deltas.empty() && !isFinite(m.tangent_deltas[i])))
        return {StatusCode::kNotFinite, strCat(where, ": a delta of entry ", i, " (vertex ",
                                               m.vertices[i], ") is not finite")};
    }
  }
  return Status::ok();
}

std::vector<double> defaultMorphWeights(const std::vector<MorphTarget>& targets) {
  std::vector<double> w;
  w.reserve(targets.size());
  for (const MorphTarget& t : targets) w.push_back(double(t.default_weight));
  return w;
}

namespace {
// v / |v|, or `fallback` where v cancelled to (nearly) zero length.
glm::dvec3 unitOr(const glm::dvec3& v, const glm::dvec3& fallback) {
  const double len = glm::length(v);
  return len > 1e-300 && std::isfinite(len) ? v / len : fallback;
}
}  // namespace

Status applyMorphTargets(const std::vector<MorphTarget>& targets, Span<const double> weights,
                         Span<glm::dvec3> positions, Span<glm::dvec3> normals,
                         Span<glm::dvec4> tangents) {
  if (weights.size() != targets.size())
    return {StatusCode::kCountMismatch, strCat("applyMorphTargets: ", weights.size(),
                                               " weights for ", targets.size(), " targets")};
  if (targets.empty()) return Status::ok();
  // The bind-pose directions, kept for a normal or tangent the deltas cancel.
  const std::vector<glm::dvec3> bind_normals(normals.begin(), normals.end());
  std::vector<glm::dvec3> bind_tangents;
  for (const glm::dvec4& t : tangents) bind_tangents.push_back(glm::dvec3(t));
  std::vector<uint8_t> touched(positions.size(), 0);
  for (size_t t = 0; t < targets.size(); ++t) {
    const double w = weights[t];
    if (w == 0.0) continue;
    const MorphTarget& m = targets[t];
    for (size_t i = 0; i < m.vertices.size(); ++i) {
      const uint32_t v = m.vertices[i];
      positions[v] += w * glm::dvec3(m.position_deltas[i]);
      if (!normals.empty() && !m.normal_deltas.empty())
        normals[v] += w * glm::dvec3(m.normal_deltas[i]);
      if (!tangents.empty() && !m.tangent_deltas.empty()) {
        const glm::dvec3 d = w * glm::dvec3(m.tangent_deltas[i]);
        tangents[v] += glm::dvec4(d, 0.0);
      }
      touched[v] = 1;
    }
  }
  for (size_t v = 0; v < positions.size(); ++v) {
    if (!touched[v]) continue;
    if (!normals.empty()) normals[v] = unitOr(normals[v], bind_normals[v]);
    if (!tangents.empty())
      tangents[v] = glm::dvec4(unitOr(glm::dvec3(tangents[v]), bind_tangents[v]), tangents[v].w);
  }
  return Status::ok();
}

}  // namespace si
