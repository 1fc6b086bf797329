// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Sockets and props (si/core/prop.h): a prop becomes a sub-mesh rigidly weighted to its
// socket's joint, placed by the socket's bind-pose frame.
#include "si/core/prop.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/str_cat.h"
#include "core/vertex_checks.h"
#include "si/core/transform.h"

namespace si {
using detail::strCat;

namespace {

bool affine(const glm::mat4& m) {
  return m[0][3] == 0.0f && m[1][3] == 0.0f && m[2][3] == 0.0f && m[3][3] == 1.0f;
}

// A unit vector perpendicular to unit `n`.
glm::vec3 perpendicular(const glm::vec3& n) {
  const glm::vec3 axis = std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  return glm::normalize(glm::cross(axis, n));
}

}  // namespace

Status makeSocket(const Skeleton& skeleton, const std::string& name, const std::string& joint_name,
                  const glm::mat4& offset, Socket* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "makeSocket: out is null"};
  if (name.empty()) return {StatusCode::kInvalidArgument, "makeSocket: the socket has no name"};
  if (!isFinite(offset))
    return {StatusCode::kNotFinite, strCat("makeSocket '", name, "': the offset is not finite")};
  if (!affine(offset))
    return {StatusCode::kInvalidArgument,
            strCat("makeSocket '", name, "': the offset's last row is not 0 0 0 1")};
  if (glm::determinant(glm::mat3(offset)) == 0.0f)
    return {StatusCode::kInvalidArgument,
            strCat("makeSocket '", name, "': the offset is not invertible")};
  int32_t joint = -1;
  for (size_t j = 0; j < skeleton.joint_names.size(); ++j) {
    if (skeleton.joint_names[j] != joint_name) continue;
    if (joint >= 0)
      return {StatusCode::kAmbiguous, strCat("makeSocket '", name, "': joints ", joint, " and ", j,
                                             " are both named '", joint_name, "'")};
    joint = int32_t(j);
  }
  if (joint < 0 || size_t(joint) >= skeleton.inverse_bind_matrices.size())
    return {StatusCode::kNotFound,
            strCat("makeSocket '", name, "': no joint named '", joint_name, "'")};
  const glm::mat4 bind =
      glm::mat4(glm::inverse(glm::dmat4(skeleton.inverse_bind_matrices[size_t(joint)])));
  Socket s;
  s.name = name;
  s.joint = uint32_t(joint);
  s.bind_frame = bind * offset;
  if (!isFinite(s.bind_frame))
    return {StatusCode::kNotFinite, strCat("makeSocket '", name, "': joint '", joint_name,
                                           "' has an inverse bind matrix that cannot be inverted")};
  *out = std::move(s);
  return Status::ok();
}

Status PropMesh::validate() const {
  const auto where = [&](const char* what) { return strCat("prop '", name, "': ", what); };
  if (name.empty()) return {StatusCode::kInvalidArgument, "prop: it has no name"};
  const size_t n = positions.size();
  if (n == 0 || indices.size() < 3)
    return {StatusCode::kInvalidArgument, where("it has no triangle")};
  if (indices.size() % 3 != 0)
    return {StatusCode::kInvalidArgument,
            strCat(where("indices: "), indices.size(), " is not a multiple of 3")};
  const auto count = [&](size_t got, const char* what, bool optional) -> Status {
    if (got == n || (optional && got == 0)) return Status::ok();
    return {StatusCode::kCountMismatch,
            strCat(where(what), " has ", got, " elements for ", n, " positions")};
  };
  Status s = count(normals.size(), "normals", false);
  if (s.isOk()) s = count(tangents.size(), "tangents", true);
  if (s.isOk()) s = count(texcoords.size(), "texcoords", true);
  if (s.isOk()) s = count(texcoords1.size(), "texcoords1", true);
  if (s.isOk()) s = count(colors.size(), "colors", true);
  if (s.isOk()) s = count(vertex_materials.size(), "vertex_materials", true);
  if (!s.isOk()) return s;
  for (size_t v = 0; v < n; ++v) {
    const bool ok = isFinite(positions[v]) && isFinite(normals[v]) &&
                    (tangents.empty() || isFinite(tangents[v])) &&
                    (texcoords.empty() || detail::isFinite2(texcoords[v])) &&
                    (texcoords1.empty() || detail::isFinite2(texcoords1[v])) &&
                    (colors.empty() || isFinite(colors[v]));
    if (!ok)
      return {StatusCode::kNotFinite,
              strCat(where("vertex "), v, " has a value that is not finite")};
    if (!colors.empty() && !detail::inUnitRange(colors[v]))
      return {StatusCode::kOutOfRange, strCat(where("vertex "), v, " has a colour outside [0, 1]")};
  }
  for (size_t i = 0; i < indices.size(); ++i)
    if (indices[i] >= n)
      return {StatusCode::kOutOfRange,
              strCat(where("index "), i, " is ", indices[i], ", not below ", n)};
  const size_t material_count = std::max<size_t>(materials.size(), 1);
  for (size_t v = 0; v < vertex_materials.size(); ++v)
    if (vertex_materials[v] >= material_count)
      return {StatusCode::kOutOfRange, strCat(where("vertex "), v, " uses material ",
                                              vertex_materials[v], " of ", materials.size())};
  for (size_t m = 0; m < materials.size(); ++m) {
    const int32_t img = materials[m].base_color_image;
    if (img < -1 || img >= int32_t(images.size()))
      return {StatusCode::kOutOfRange,
              strCat(where("material "), m, " uses image ", img, " of ", images.size())};
  }
  for (size_t i = 0; i < images.size(); ++i) {
    s = images[i].validate();
    if (!s.isOk()) return {s.code(), strCat(where("image "), i, ": ", s.message())};
  }
  return Status::ok();
}

Status attachProp(const Socket& socket, const PropMesh& prop, Character* character,
                  uint32_t* sub_mesh) {
  if (character == nullptr) return {StatusCode::kInvalidArgument, "attachProp: character is null"};
  Status s = prop.validate();
  if (!s.isOk()) return {s.code(), "attachProp: " + s.message()};
  const glm::mat4& frame = socket.bind_frame;
  const float det = glm::determinant(glm::mat3(frame));
  if (!isFinite(frame) || !affine(frame) || det == 0.0f || !std::isfinite(det))
    return {StatusCode::kInvalidArgument,
            strCat("attachProp: socket '", socket.name,
                   "' has a frame that is not finite, affine and invertible")};
  if (socket.joint >= character->skeleton.jointCount())
    return {StatusCode::kOutOfRange,
            strCat("attachProp: socket '", socket.name, "' follows joint ", socket.joint, " of ",
                   character->skeleton.jointCount())};
  SkinnedMesh& mesh = character->mesh;
  if (mesh.sub_meshes.size() >= SkinnedMesh::kMaxSubMeshes)
    return {StatusCode::kLimitExceeded, strCat("attachProp: the mesh has ", mesh.sub_meshes.size(),
                                               " sub-meshes, the most a variation mask switches")};
  for (const SubMesh& sm : mesh.sub_meshes)
    if (sm.name == prop.name)
      return {StatusCode::kInvalidArgument,
              strCat("attachProp: a sub-mesh is named '", prop.name, "' already")};
  const size_t first_vertex = mesh.positions.size();
  const size_t n = prop.positions.size();
  const size_t prop_materials = std::max<size_t>(prop.materials.size(), 1);
  // The character's materials as they resolve now (none: one default white), then the prop's.
  const size_t first_material = std::max<size_t>(character->materials.size(), 1);
  if (first_vertex + n > std::numeric_limits<uint32_t>::max() ||
      mesh.indices.size() + prop.indices.size() > std::numeric_limits<uint32_t>::max())
    return {StatusCode::kLimitExceeded, "attachProp: the mesh would pass 2^32 vertices or indices"};
  if (first_material + prop_materials > std::numeric_limits<uint16_t>::max())
    return {StatusCode::kLimitExceeded, "attachProp: the character would pass 65535 materials"};

  // Everything is built in a copy, so a failure above or below leaves the character untouched.
  Character c = *character;
  SkinnedMesh& m = c.mesh;
  if (m.vertex_materials.empty()) m.vertex_materials = resolvedVertexMaterials(m);
  if (c.materials.empty()) c.materials.push_back(Material{"default", glm::vec4(1.0f), -1});
  const int32_t first_image = int32_t(c.images.size());
  for (const Material& pm : prop.materials) {
    Material copy = pm;
    if (copy.base_color_image >= 0) copy.base_color_image += first_image;
    c.materials.push_back(std::move(copy));
  }
  if (prop.materials.empty()) c.materials.push_back(Material{prop.name, glm::vec4(1.0f), -1});
  c.images.insert(c.images.end(), prop.images.begin(), prop.images.end());

  const glm::mat3 linear(frame);
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
  const float handedness = det < 0.0f ? -1.0f : 1.0f;
  const bool tangents = !m.tangents.empty() || (first_vertex == 0 && !prop.tangents.empty());
  const bool texcoords = !m.texcoords.empty() || !prop.texcoords.empty();
  if (texcoords && m.texcoords.empty()) m.texcoords.assign(first_vertex, glm::vec2(0.0f));
  const bool texcoords1 = !m.texcoords1.empty() || !prop.texcoords1.empty();
  if (texcoords1 && m.texcoords1.empty()) m.texcoords1.assign(first_vertex, glm::vec2(0.0f));
  const bool colors = !m.colors.empty() || !prop.colors.empty();
  if (colors && m.colors.empty()) m.colors.assign(first_vertex, glm::vec4(1.0f));
  for (size_t v = 0; v < n; ++v) {
    m.positions.push_back(glm::vec3(frame * glm::vec4(prop.positions[v], 1.0f)));
    const glm::vec3 nrm = normal_matrix * prop.normals[v];
    const float len = glm::length(nrm);
    m.normals.push_back(len > 0.0f ? nrm / len : glm::vec3(0, 1, 0));
    if (tangents) {
      glm::vec3 t = prop.tangents.empty() ? glm::vec3(0.0f) : linear * glm::vec3(prop.tangents[v]);
      t -= m.normals.back() * glm::dot(m.normals.back(), t);  // Orthogonal to the new normal.
      const float tl = glm::length(t);
      const float w = prop.tangents.empty() ? 1.0f : prop.tangents[v].w * handedness;
      m.tangents.push_back(glm::vec4(tl > 1e-6f ? t / tl : perpendicular(m.normals.back()), w));
    }
    if (texcoords)
      m.texcoords.push_back(prop.texcoords.empty() ? glm::vec2(0.0f) : prop.texcoords[v]);
    if (texcoords1)
      m.texcoords1.push_back(prop.texcoords1.empty() ? glm::vec2(0.0f) : prop.texcoords1[v]);
    if (colors) m.colors.push_back(prop.colors.empty() ? glm::vec4(1.0f) : prop.colors[v]);
    m.joints.push_back(glm::u16vec4(uint16_t(socket.joint), 0, 0, 0));
    m.weights.push_back(glm::vec4(1, 0, 0, 0));
    if (!m.joints1.empty()) {  // A character with 8 influences: the prop has no more than 1.
      m.joints1.push_back(glm::u16vec4(0));
      m.weights1.push_back(glm::vec4(0.0f));
    }
    m.vertex_materials.push_back(
        uint16_t(first_material + (prop.vertex_materials.empty() ? 0 : prop.vertex_materials[v])));
  }
  SubMesh part;
  part.name = prop.name;
  part.material =
      uint32_t(first_material + (prop.vertex_materials.empty() ? 0 : prop.vertex_materials[0]));
  part.lods.push_back({uint32_t(m.indices.size()), uint32_t(prop.indices.size())});
  // Errors known for the other parts: LOD 0's is 0.
  const bool errors = std::any_of(m.sub_meshes.begin(), m.sub_meshes.end(),
                                  [](const SubMesh& sm) { return !sm.lod_error_units.empty(); });
  if (errors) part.lod_error_units = {0.0f};
  for (size_t i = 0; i < prop.indices.size(); i += 3) {
    const uint32_t a = prop.indices[i], b = prop.indices[i + 1], d = prop.indices[i + 2];
    const uint32_t base = uint32_t(first_vertex);
    m.indices.insert(m.indices.end(),
                     {base + a, base + (det < 0.0f ? d : b), base + (det < 0.0f ? b : d)});
  }
  m.sub_meshes.push_back(std::move(part));
  s = c.validate();
  if (!s.isOk()) return {s.code(), "attachProp: " + s.message()};
  if (sub_mesh != nullptr) *sub_mesh = uint32_t(m.sub_meshes.size() - 1);
  *character = std::move(c);
  return Status::ok();
}

}  // namespace si
