// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Tangent generation (si/core/tangents.h): per triangle, the position derivatives along u and
// v (E1 = dp1, E2 = dp2, (du1, dv1), (du2, dv2): T = (dv2 E1 - dv1 E2) / det, dp/dv = (du1 E2
// - du2 E1) / det, B = -dp/dv: up in the image), added to each corner's vertex weighted by
// the corner's angle; per vertex, T made orthogonal to N (Gram-Schmidt) and normalized, w the
// sign of dot(cross(N, T), B).
#include "si/core/tangents.h"

#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "core/str_cat.h"

namespace si {
using detail::strCat;

namespace {

// Per vertex: the angle-weighted tangents and bitangents of its triangles.
struct Accumulated {
  explicit Accumulated(size_t n) : t(n), b(n), touched(n) {}
  std::vector<glm::dvec3> t, b;
  std::vector<bool> touched;
};

// Adds the frames of triangles [first, first + count) of `indices`.
void accumulate(const SkinnedMesh& m, uint32_t first, uint32_t count, Accumulated* acc) {
  for (uint32_t i = first; i < first + count; i += 3) {
    const uint32_t v[3] = {m.indices[i], m.indices[i + 1], m.indices[i + 2]};
    const glm::dvec3 p0(m.positions[v[0]]), p1(m.positions[v[1]]), p2(m.positions[v[2]]);
    const glm::dvec2 t0(m.texcoords[v[0]]), t1(m.texcoords[v[1]]), t2(m.texcoords[v[2]]);
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::dvec2 d1 = t1 - t0, d2 = t2 - t0;
    const double det = d1.x * d2.y - d2.x * d1.y;
    if (!(std::abs(det) > 1e-20) || glm::length(glm::cross(e1, e2)) <= 0.0) continue;
    const glm::dvec3 t = (d2.y * e1 - d1.y * e2) / det;
    const glm::dvec3 b = (d2.x * e1 - d1.x * e2) / det;  // -dp/dv.
    const glm::dvec3 p[3] = {p0, p1, p2};
    for (int c = 0; c < 3; ++c) {
      const glm::dvec3 a = p[(c + 1) % 3] - p[c], d = p[(c + 2) % 3] - p[c];
      const double la = glm::length(a), ld = glm::length(d);
      if (la <= 0.0 || ld <= 0.0) continue;
      const double angle = std::acos(glm::clamp(glm::dot(a, d) / (la * ld), -1.0, 1.0));
      acc->t[v[c]] += angle * t;
      acc->b[v[c]] += angle * b;
      acc->touched[v[c]] = true;
    }
  }
}

// A unit vector perpendicular to unit `n`.
glm::dvec3 perpendicularTo(const glm::dvec3& n) {
  const glm::dvec3 axis = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(n, axis));
}

}  // namespace

Status generateTangents(SkinnedMesh* mesh, TangentReport* report) {
  if (mesh == nullptr) return {StatusCode::kInvalidArgument, "generateTangents: null mesh"};
  const size_t n = mesh->positions.size();
  if (mesh->texcoords.size() != n || n == 0)
    return {StatusCode::kInvalidArgument,
            strCat("generateTangents: the mesh has ", mesh->texcoords.size(),
                   " texture coordinates for ", n, " vertices: tangents follow them")};
  if (mesh->normals.size() != n)
    return {StatusCode::kInvalidArgument,
            strCat("generateTangents: ", mesh->normals.size(), " normals for ", n, " vertices")};
  for (size_t i = 0; i < mesh->indices.size(); ++i)
    if (mesh->indices[i] >= n)
      return {StatusCode::kOutOfRange,
              strCat("generateTangents: index ", i, " is ", mesh->indices[i], " of ", n, " vertices")};
  const auto rangeOk = [&](const IndexRange& r) {
    return r.index_count % 3 == 0 && uint64_t(r.first_index) + r.index_count <= mesh->indices.size();
  };
  Accumulated acc(n);
  for (const SubMesh& sm : mesh->sub_meshes)
    if (!sm.lods.empty() && rangeOk(sm.lods[0]))
      accumulate(*mesh, sm.lods[0].first_index, sm.lods[0].index_count, &acc);
  // Vertices only coarser levels use: their levels' triangles, added to those vertices only.
  Accumulated coarse(n);
  for (const SubMesh& sm : mesh->sub_meshes)
    for (size_t l = 1; l < sm.lods.size(); ++l)
      if (rangeOk(sm.lods[l])) accumulate(*mesh, sm.lods[l].first_index, sm.lods[l].index_count, &coarse);
  TangentReport r;
  std::vector<glm::vec4> tangents(n);
  for (size_t v = 0; v < n; ++v) {
    const bool fine = acc.touched[v];
    const glm::dvec3 t = fine ? acc.t[v] : coarse.t[v], b = fine ? acc.b[v] : coarse.b[v];
    const glm::dvec3 raw(mesh->normals[v]);
    const glm::dvec3 normal = glm::length(raw) > 0.0 ? glm::normalize(raw) : glm::dvec3(0, 0, 1);
    glm::dvec3 ortho = t - normal * glm::dot(normal, t);
    const double len = glm::length(ortho);
    double w = 1.0;
    if ((fine || coarse.touched[v]) && len > 1e-12 * std::max(1.0, glm::length(t))) {
      ortho /= len;
      w = glm::dot(glm::cross(normal, ortho), b) < 0.0 ? -1.0 : 1.0;
    } else {
      ortho = perpendicularTo(normal);
      ++r.degenerate;
    }
    if (w < 0.0) ++r.mirrored;
    tangents[v] = glm::vec4(glm::vec3(ortho), float(w));
  }
  r.vertices = n;
  mesh->tangents = std::move(tangents);
  if (report != nullptr) *report = r;
  return Status::ok();
}

}  // namespace si
