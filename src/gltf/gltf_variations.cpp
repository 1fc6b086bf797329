// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Parts and variations: every skinned primitive is a part (with its "_LOD<n>" levels); parts
// go into variation groups (GltfImportDesc: explicit groups, the "VAR_" naming convention or
// one group per mesh), and each group becomes one sub-mesh whose LOD k concatenates its parts'
// LOD k (a part with fewer levels repeats its coarsest). Each vertex keeps its part's material.
#include <algorithm>
#include <cctype>
#include <map>
#include <set>
#include <tuple>

#include "gltf/gltf_convert.h"

namespace si::detail {

namespace {

constexpr const char* kBaseGroup = "base";

// "VAR_Helmet" (any case) -> "Helmet"; anything else -> "".
std::string conventionGroup(const std::string& name) {
  if (name.size() <= 4) return {};
  std::string prefix = name.substr(0, 4);
  for (char& ch : prefix) ch = char(std::toupper(static_cast<unsigned char>(ch)));
  return prefix == "VAR_" ? name.substr(4) : std::string();
}

struct Part {
  uint32_t group = 0;
  std::map<uint32_t, const ImportedPrimitive*> lods;  // By level.
};

struct GroupBuild {
  std::string name, source;
  std::vector<const Part*> parts;
};

}  // namespace

Status groupVariations(const std::vector<ImportedPrimitive>& primitives,
                       const GltfImportDesc& desc, GltfImportReport* report, Character* c) {
  // Explicit groups: mesh or node name -> group name.
  std::map<std::string, std::string> named;
  std::set<std::string> group_names;
  for (const VariationGroupDesc& g : desc.variation_groups) {
    if (g.name.empty())
      return {StatusCode::kInvalidArgument, "glTF import: a variation group has no name"};
    if (!group_names.insert(g.name).second)
      return {StatusCode::kInvalidArgument,
              strCat("glTF import: variation group '", g.name, "' is given twice")};
    for (const std::string& mesh : g.meshes) {
      const bool found = std::any_of(primitives.begin(), primitives.end(), [&](const auto& p) {
        return p.mesh_name == mesh || p.node_name == mesh;
      });
      if (!found)
        return {StatusCode::kNotFound,
                strCat("glTF import: variation group '", g.name, "' names mesh '", mesh,
                       "', which no skinned primitive has")};
      named[mesh] = g.name;
    }
  }
  // The group of each primitive, and the parts (mesh, primitive index) with their levels.
  std::vector<GroupBuild> groups;
  std::map<std::string, uint32_t> group_index;
  // Keyed by mesh, primitive and use: a mesh several nodes move rigidly (instanced wheels) is a
  // part for each node's use (the n-th use of a level joins the n-th use of the others).
  std::map<std::tuple<std::string, uint32_t, uint32_t>, Part> parts;
  std::map<std::tuple<std::string, uint32_t, uint32_t>, uint32_t> rigid_uses;
  std::vector<const Part*> part_order;
  for (const ImportedPrimitive& p : primitives) {
    std::string name, source;
    if (named.count(p.mesh_name)) {
      name = named[p.mesh_name], source = "option";
    } else if (named.count(p.node_name)) {
      name = named[p.node_name], source = "option";
    } else if (desc.variations == VariationSource::kEachMesh) {
      name = p.mesh_name, source = "each mesh";
    } else {
      name = conventionGroup(p.mesh_name);
      if (name.empty()) name = conventionGroup(p.node_name);
      source = name.empty() ? "always worn" : "convention";
      if (name.empty()) name = kBaseGroup;
    }
    auto [it, added] = group_index.emplace(name, uint32_t(groups.size()));
    if (added) groups.push_back({name, source, {}});
    const uint32_t use = p.rigid ? rigid_uses[{p.mesh_name, p.primitive, p.lod}]++ : 0;
    Part& part = parts[{p.mesh_name, p.primitive, use}];
    if (part.lods.empty()) {
      part.group = it->second;
      part_order.push_back(&part);
      groups[it->second].parts.push_back(&part);
    } else if (part.group != it->second) {
      return corrupt(strCat("mesh '", p.mesh_name, "' primitive ", p.primitive,
                            ": its LOD levels fall in two variation groups"));
    }
    if (!part.lods.emplace(p.lod, &p).second)
      return corrupt(strCat("two meshes claim part '", p.mesh_name, "' primitive ", p.primitive,
                            " LOD ", p.lod));
  }
  if (groups.size() > SkinnedMesh::kMaxSubMeshes)
    return {StatusCode::kLimitExceeded,
            strCat("glTF import: ", groups.size(), " variation groups (at most ",
                   SkinnedMesh::kMaxSubMeshes, "); group meshes with GltfImportDesc::"
                   "variation_groups or the \"VAR_<group>\" naming convention")};
  // The always-worn group first (sub-mesh 0), the others in order of appearance.
  std::stable_partition(groups.begin(), groups.end(),
                        [](const GroupBuild& g) { return g.source == "always worn"; });
  SkinnedMesh& mesh = c->mesh;
  mesh.vertex_materials.assign(mesh.vertexCount(), 0);
  for (const ImportedPrimitive& p : primitives)
    for (uint32_t v : p.indices) mesh.vertex_materials[v] = uint16_t(p.material);
  report->parts = uint32_t(part_order.size());
  for (const GroupBuild& g : groups) {
    SubMesh sm;
    sm.name = g.name;
    size_t levels = 0;
    std::set<uint32_t> materials;
    for (const Part* part : g.parts) {
      levels = std::max(levels, part->lods.size());
      for (const auto& [lod, prim] : part->lods) materials.insert(prim->material);
    }
    sm.material = g.parts.front()->lods.begin()->second->material;
    for (size_t k = 0; k < levels; ++k) {
      IndexRange r{uint32_t(mesh.indices.size()), 0};
      for (const Part* part : g.parts) {
        auto it = part->lods.begin();
        std::advance(it, std::min(k, part->lods.size() - 1));
        const std::vector<uint32_t>& idx = it->second->indices;
        mesh.indices.insert(mesh.indices.end(), idx.begin(), idx.end());
        r.index_count += uint32_t(idx.size());
      }
      sm.lods.push_back(r);
    }
    mesh.sub_meshes.push_back(std::move(sm));
    report->groups.push_back({g.name, uint32_t(g.parts.size()), uint32_t(materials.size()), g.source});
  }
  return Status::ok();
}

}  // namespace si::detail
