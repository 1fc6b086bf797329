// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Node matrices (glTF 2.0 specification, "Transformations": matrix, or T * R * S) and surfaces
// placed by them: what a prop's meshes and a character's rigid parts (meshes moved by their
// node rather than a skin) are made of.
#include <cmath>

#include "gltf/gltf_convert.h"

namespace si::detail {

glm::dmat4 nodeMatrix(const tinygltf::Node& n) {
  glm::dmat4 m(1.0);
  if (n.matrix.size() == 16) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[size_t(c * 4 + r)];
    return m;
  }
  if (n.translation.size() == 3)
    m[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
  if (n.rotation.size() == 4) {
    const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
    const glm::dmat3 r = glm::mat3_cast(glm::normalize(q));
    for (int c = 0; c < 3; ++c) m[c] = glm::dvec4(r[c], 0.0);
  }
  if (n.scale.size() == 3)
    for (int c = 0; c < 3; ++c) m[c] *= n.scale[size_t(c)];
  return m;
}

void placeSurface(const glm::dmat4& m, PrimitiveSurface* s) {
  const glm::dmat3 linear(m);
  const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
  const double det = glm::determinant(linear);
  const auto unit = [](const glm::dvec3& v, const glm::vec3& fallback) {
    const double len = glm::length(v);
    return len > 0.0 && std::isfinite(len) ? glm::vec3(v / len) : fallback;
  };
  for (glm::vec3& p : s->positions) p = glm::vec3(m * glm::dvec4(glm::dvec3(p), 1.0));
  for (glm::vec3& n : s->normals) n = unit(normal_matrix * glm::dvec3(n), glm::vec3(0, 1, 0));
  for (glm::vec4& t : s->tangents) {
    const glm::vec3 xyz = unit(linear * glm::dvec3(t), glm::vec3(1, 0, 0));
    t = glm::vec4(xyz, det < 0.0 ? -t.w : t.w);  // A mirror flips the bitangent's side.
  }
  if (det < 0.0)  // A mirror turns the triangles over: wound back so fronts stay outside.
    for (size_t i = 0; i + 2 < s->indices.size(); i += 3)
      std::swap(s->indices[i + 1], s->indices[i + 2]);
}

}  // namespace si::detail
