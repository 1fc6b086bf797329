// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A prop from a glTF file (si/gltf/gltf_prop.h): the scene's triangle primitives at their nodes'
// world matrices (glTF 2.0 specification, "Transformations": matrix, or T * R * S; a skinned
// node's own transform does not apply to its mesh), materials as a character's.
#include "si/gltf/gltf_prop.h"

#include <cmath>

#include "gltf/gltf_convert.h"

namespace si {
using detail::corrupt;
using detail::strCat;

namespace {

// Which optional attributes some primitive of the prop has (the others get 0 and white).
struct OptionalAttributes {
  bool texcoords1 = false;
  bool colors = false;
};

// Appends primitive `p` of node `node` at world matrix `world` to `out`.
Status addPrimitive(const tinygltf::Model& m, const tinygltf::Node& node, size_t p,
                    const glm::dmat4& world, GltfImportReport* report, PropMesh* out,
                    OptionalAttributes* seen) {
  const tinygltf::Mesh& mesh = m.meshes[size_t(node.mesh)];
  const tinygltf::Primitive& prim = mesh.primitives[p];
  const std::string where =
      strCat("mesh '", mesh.name.empty() ? node.name : mesh.name, "' primitive ", p);
  if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
    report->warnings.push_back(where + ": not a triangle list: skipped");
    return Status::ok();
  }
  if (!prim.targets.empty()) report->warnings.push_back(where + ": morph targets ignored");
  if (prim.material >= 0 && size_t(prim.material) >= m.materials.size())
    return corrupt(strCat(where, ": material ", prim.material, " does not exist"));
  detail::PrimitiveSurface surface;
  const Status s = detail::readPrimitiveSurface(m, prim, where, &surface);
  if (!s.isOk()) return s;
  if (surface.positions.empty()) {
    report->warnings.push_back(where + ": no vertices: skipped");
    return Status::ok();
  }
  if (surface.generated_normals)
    report->warnings.push_back(where + ": no NORMAL: generated smooth normals");
  if (surface.clamped_colors != 0)
    report->warnings.push_back(
        strCat(where, ": ", surface.clamped_colors, " COLOR_0 values outside [0, 1] clamped"));
  seen->texcoords1 = seen->texcoords1 || surface.has_texcoords1;
  seen->colors = seen->colors || surface.has_colors;
  out->texcoords1.insert(out->texcoords1.end(), surface.texcoords1.begin(),
                         surface.texcoords1.end());
  out->colors.insert(out->colors.end(), surface.colors.begin(), surface.colors.end());
  detail::placeSurface(world, &surface);
  const uint32_t first = uint32_t(out->positions.size());
  out->positions.insert(out->positions.end(), surface.positions.begin(), surface.positions.end());
  out->normals.insert(out->normals.end(), surface.normals.begin(), surface.normals.end());
  out->texcoords.insert(out->texcoords.end(), surface.texcoords.begin(), surface.texcoords.end());
  out->vertex_materials.insert(out->vertex_materials.end(), surface.positions.size(),
                               uint16_t(prim.material >= 0 ? prim.material + 1 : 0));
  for (uint32_t i : surface.indices) out->indices.push_back(first + i);
  return Status::ok();
}

Status convertProp(const tinygltf::Model& m, const GltfPropDesc& desc, PropMesh* out,
                   GltfImportReport* report) {
  if (m.materials.size() >= 65535)
    return {StatusCode::kLimitExceeded, "glTF: more than 65534 materials"};
  // Roots: the default scene's nodes (the first scene's without one), or every node no other
  // node names as a child.
  std::vector<int> roots;
  if (!m.scenes.empty()) {
    const size_t scene = m.defaultScene >= 0 && size_t(m.defaultScene) < m.scenes.size()
                             ? size_t(m.defaultScene)
                             : 0;
    roots = m.scenes[scene].nodes;
  } else {
    std::vector<bool> child(m.nodes.size(), false);
    for (const tinygltf::Node& n : m.nodes)
      for (int c : n.children)
        if (c >= 0 && size_t(c) < m.nodes.size()) child[size_t(c)] = true;
    for (size_t n = 0; n < m.nodes.size(); ++n)
      if (!child[n]) roots.push_back(int(n));
  }
  PropMesh prop;
  OptionalAttributes optional;
  std::vector<bool> seen(m.nodes.size(), false);
  std::vector<std::pair<int, glm::dmat4>> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, glm::dmat4(1.0));
  while (!stack.empty()) {
    const auto [index, parent] = stack.back();
    stack.pop_back();
    if (index < 0 || size_t(index) >= m.nodes.size())
      return corrupt(strCat("node ", index, " does not exist"));
    if (seen[size_t(index)])
      return corrupt(strCat("node ", index, " is reached twice: the node hierarchy is not a tree"));
    seen[size_t(index)] = true;
    const tinygltf::Node& node = m.nodes[size_t(index)];
    const glm::dmat4 world = parent * detail::nodeMatrix(node);
    if (node.mesh >= 0) {
      if (size_t(node.mesh) >= m.meshes.size())
        return corrupt(strCat("node ", index, " names mesh ", node.mesh, ", which does not exist"));
      if (prop.name.empty()) prop.name = m.meshes[size_t(node.mesh)].name;
      const glm::dmat4 placed = node.skin >= 0 ? glm::dmat4(1.0) : world;  // Skinned: bind pose.
      for (size_t p = 0; p < m.meshes[size_t(node.mesh)].primitives.size(); ++p) {
        const Status s = addPrimitive(m, node, p, placed, report, &prop, &optional);
        if (!s.isOk()) return s;
      }
    }
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
      stack.emplace_back(*c, world);
  }
  if (prop.indices.empty())
    return {StatusCode::kUnsupported, "glTF: the file has no triangle for a prop"};
  if (!optional.texcoords1) prop.texcoords1.clear();
  if (!optional.colors) prop.colors.clear();
  if (desc.scale != 1.0f)
    for (glm::vec3& p : prop.positions) p *= desc.scale;
  Character materials;  // Materials and images exactly as a character's import makes them.
  detail::convertMaterials(m, report, &materials);
  prop.materials = std::move(materials.materials);
  prop.images = std::move(materials.images);
  report->materials = uint32_t(prop.materials.size());
  report->images = uint32_t(prop.images.size());
  if (!desc.name.empty()) prop.name = desc.name;
  if (prop.name.empty()) prop.name = "prop";
  const Status s = prop.validate();
  if (!s.isOk()) return s;
  *out = std::move(prop);
  return Status::ok();
}

}  // namespace

Status importGltfPropMemory(Span<const uint8_t> bytes, const std::string& base_dir,
                            const GltfPropDesc& desc, PropMesh* out, GltfImportReport* report) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "importGltfProp: out is null"};
  if (!std::isfinite(desc.scale) || desc.scale <= 0.0f)
    return {StatusCode::kInvalidArgument,
            strCat("importGltfProp: scale ", desc.scale, " is not finite and positive")};
  return detail::parseAndConvert(bytes, base_dir, desc.load_images, report,
                                 [&](const tinygltf::Model& model, GltfImportReport* r) {
                                   return convertProp(model, desc, out, r);
                                 });
}

Status importGltfPropFile(const std::string& path, const GltfPropDesc& desc, PropMesh* out,
                          GltfImportReport* report) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "importGltfProp: out is null"};
  detail::GltfFile file;
  const Status s = detail::readGltfFile(path, &file);
  return s.isOk() ? importGltfPropMemory(file.bytes, file.dir, desc, out, report) : s;
}

}  // namespace si
