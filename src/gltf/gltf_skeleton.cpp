// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The character's skeleton (glTF 2.0 specification, "Skins", "Transformations"): the chosen
// skin's joints, the nodes whose meshes no skin moves (rigid parts: a file animated by its
// nodes, a prop held by a joint) and every ancestor of them, parents first, with rest poses and
// inverse bind matrices.
#include <algorithm>
#include <cmath>
#include <set>

#include "gltf/gltf_convert.h"

namespace si::detail {

namespace {

Transform nodeTransform(const tinygltf::Node& n, std::vector<std::string>* warnings) {
  Transform t;
  if (n.matrix.size() == 16) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[size_t(c * 4 + r)];
    t.translation = glm::vec3(m[3]);
    glm::dvec3 s(glm::length(glm::dvec3(m[0])), glm::length(glm::dvec3(m[1])),
                 glm::length(glm::dvec3(m[2])));
    if (glm::determinant(glm::dmat3(m)) < 0.0) s.x = -s.x;
    glm::dmat3 r(glm::dvec3(m[0]) / (s.x != 0 ? s.x : 1), glm::dvec3(m[1]) / (s.y != 0 ? s.y : 1),
                 glm::dvec3(m[2]) / (s.z != 0 ? s.z : 1));
    const double shear = std::fabs(glm::dot(r[0], r[1])) + std::fabs(glm::dot(r[1], r[2])) +
                         std::fabs(glm::dot(r[0], r[2]));
    if (shear > 1e-4)
      warnings->push_back(strCat("node '", n.name, "': its matrix has shear, which TRS cannot "
                                 "hold; approximated"));
    const glm::dquat q = glm::quat_cast(r);
    t.rotation = glm::quat(float(q.w), float(q.x), float(q.y), float(q.z));
    t.scale = glm::vec3(s);
    return t;
  }
  if (n.translation.size() == 3)
    t.translation = glm::vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]));
  if (n.rotation.size() == 4)
    t.rotation = glm::quat(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]),
                           float(n.rotation[2]));
  if (n.scale.size() == 3) t.scale = glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2]));
  return t;
}

// The chosen skin (GltfImportDesc), or -1 when the file has none and none was asked for.
Status chooseSkin(const tinygltf::Model& m, const GltfImportDesc& desc, int* out) {
  int skin_index = desc.skin_index;
  if (skin_index >= 0 && size_t(skin_index) >= m.skins.size())
    return {StatusCode::kNotFound, strCat("glTF: skin ", skin_index, " does not exist (",
                                          m.skins.size(), " skins)")};
  if (skin_index < 0) {
    if (!desc.skin_name.empty()) {
      for (size_t i = 0; i < m.skins.size(); ++i)
        if (m.skins[i].name == desc.skin_name) skin_index = int(i);
      if (skin_index < 0)
        return {StatusCode::kNotFound, strCat("glTF: no skin named '", desc.skin_name, "'")};
    } else if (m.skins.size() == 1) {
      skin_index = 0;
    } else if (m.skins.size() > 1) {
      return {StatusCode::kAmbiguous, strCat("glTF: the asset has ", m.skins.size(),
                                             " skins; choose one by index or name")};
    }
  }
  *out = skin_index;
  return Status::ok();
}

}  // namespace

Status convertSkeleton(const tinygltf::Model& m, const GltfImportDesc& desc,
                       GltfImportReport* report, Character* c, SkinBinding* out) {
  std::vector<std::string>& warnings = report->warnings;
  // ---- The skin, when the file has one.
  int skin_index = -1;
  Status chosen = chooseSkin(m, desc, &skin_index);
  if (!chosen.isOk()) return chosen;
  const tinygltf::Skin* skin = skin_index >= 0 ? &m.skins[size_t(skin_index)] : nullptr;
  if (skin != nullptr && skin->joints.empty())
    return corrupt(strCat("skin ", skin_index, " has no joints"));
  report->skin_joints = skin != nullptr ? uint32_t(skin->joints.size()) : 0;
  const size_t node_count = m.nodes.size();
  std::vector<int> parent(node_count, -1);
  for (size_t n = 0; n < node_count; ++n)
    for (int child : m.nodes[n].children) {
      if (child < 0 || size_t(child) >= node_count)
        return corrupt(strCat("node ", n, " has child ", child, ", which does not exist"));
      if (parent[size_t(child)] != -1)
        return corrupt(strCat("node ", child, " has two parents"));
      parent[size_t(child)] = int(n);
    }
  // The skeleton: the skin's joints, the nodes whose meshes no skin moves (rigid parts, moved by
  // their node: a file animated by its nodes, or a prop held by a joint), and every ancestor of
  // them, parents first.
  std::set<int> members;
  const auto withAncestors = [&](int j) {
    size_t steps = 0;
    for (int n = j; n >= 0; n = parent[size_t(n)]) {
      if (++steps > node_count)
        return corrupt(strCat("the node hierarchy has a cycle at node ", j));
      members.insert(n);
    }
    return Status::ok();
  };
  std::vector<bool> skin_joint(node_count, false);
  if (skin != nullptr)
    for (int j : skin->joints) {
      if (j < 0 || size_t(j) >= node_count)
        return corrupt(
            strCat("skin ", skin_index, " names joint node ", j, ", which does not exist"));
      skin_joint[size_t(j)] = true;
      Status s = withAncestors(j);
      if (!s.isOk()) return s;
    }
  std::vector<int> rigid;  // Those that are not a skin's joints too (they keep the skin's bind).
  for (size_t n = 0; n < node_count; ++n)
    if (m.nodes[n].mesh >= 0 && m.nodes[n].skin < 0) {
      if (!skin_joint[n]) rigid.push_back(int(n));
      Status s = withAncestors(int(n));
      if (!s.isOk()) return s;
    }
  if (members.empty())
    return {StatusCode::kUnsupported, "glTF: the asset has no skin and no node with a mesh"};
  std::vector<std::pair<size_t, int>> by_depth;
  for (int n : members) {
    size_t depth = 0;
    for (int p = parent[size_t(n)]; p >= 0; p = parent[size_t(p)]) ++depth;
    by_depth.push_back({depth, n});
  }
  std::sort(by_depth.begin(), by_depth.end());
  std::vector<int32_t> node_to_joint(node_count, -1);
  std::vector<glm::dmat4> world;  // Each joint's rest matrix in the scene, parents first.
  for (const auto& [depth, n] : by_depth) {
    (void)depth;
    node_to_joint[size_t(n)] = int32_t(c->skeleton.parents.size());
    const tinygltf::Node& node = m.nodes[size_t(n)];
    const int32_t p = parent[size_t(n)] >= 0 ? node_to_joint[size_t(parent[size_t(n)])] : -1;
    c->skeleton.joint_names.push_back(node.name.empty() ? strCat("node", n) : node.name);
    c->skeleton.parents.push_back(p);
    c->skeleton.rest_pose.push_back(nodeTransform(node, &warnings));
    // The identity unless a rigid part's or the skin's (without them, the specification's
    // default), below.
    c->skeleton.inverse_bind_matrices.push_back(glm::mat4(1.0f));
    const glm::dmat4 local = TransformD::fromFloat(c->skeleton.rest_pose.back()).toMatrix();
    world.push_back(p >= 0 ? world[size_t(p)] * local : local);
  }
  // A rigid part's joint binds it where it rests: its inverse bind matrix undoes the node's
  // rest matrix (as the reference evaluator composes it; a skin's joint keeps the skin's). A node
  // that rests at zero scale (a part that pops in by scaling up) has no inverse: its part stays
  // bound in its own space.
  for (int n : rigid) {
    const size_t j = size_t(node_to_joint[size_t(n)]);
    const glm::mat4 inverse(glm::inverse(world[j]));
    if (std::fabs(glm::determinant(glm::dmat3(world[j]))) > 1e-18 && isFinite(inverse)) {
      c->skeleton.inverse_bind_matrices[j] = inverse;
    } else {
      warnings.push_back(strCat("node '", c->skeleton.joint_names[j],
                                "' rests at zero scale: its mesh is bound in its own space"));
    }
  }
  if (skin != nullptr && skin->inverseBindMatrices >= 0) {
    std::vector<double> ibm;
    Status s = readAccessor(m, skin->inverseBindMatrices, {TINYGLTF_TYPE_MAT4}, kFloat,
                            strCat("skin ", skin_index, " inverse bind matrices"), &ibm);
    if (!s.isOk()) return s;
    if (ibm.size() != skin->joints.size() * 16)
      return corrupt(strCat("skin ", skin_index, ": ", ibm.size() / 16,
                            " inverse bind matrices for ", skin->joints.size(), " joints"));
    for (size_t k = 0; k < skin->joints.size(); ++k) {
      glm::mat4 mat;
      for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) mat[col][row] = float(ibm[k * 16 + size_t(col * 4 + row)]);
      c->skeleton.inverse_bind_matrices[size_t(node_to_joint[size_t(skin->joints[k])])] = mat;
    }
  }
  out->skin_index = skin_index;
  out->skin = skin;
  out->node_to_joint = std::move(node_to_joint);
  return Status::ok();
}

}  // namespace si::detail
