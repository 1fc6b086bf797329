// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Meshes (glTF 2.0 specification, "Meshes"): every triangle primitive of every node skinned by
// the skin or moved by its node alone (a rigid part, bound wholly to its node's joint), with up to
// 8 influences reduced to 4, appended to the vertex arrays; its mesh name without the "_LOD<n>"
// suffix and its level (grouping into sub-meshes: gltf_variations.cpp; generated LODs and every
// LOD's error: gltf_import.cpp, after the weights are normalized).
#include <algorithm>
#include <cmath>

#include "gltf/gltf_convert.h"

namespace si::detail {

namespace {

// "Body_LOD2" -> ("Body", 2); names without the suffix are LOD 0.
std::pair<std::string, uint32_t> lodName(const std::string& name) {
  const size_t at = name.rfind("_LOD");
  if (at == std::string::npos || at + 4 >= name.size()) return {name, 0};
  uint32_t lod = 0;
  for (size_t i = at + 4; i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9' || lod > 1000) return {name, 0};
    lod = lod * 10 + uint32_t(name[i] - '0');
  }
  return {name.substr(0, at), lod};
}

}  // namespace

Status readPrimitiveSurface(const tinygltf::Model& m, const tinygltf::Primitive& prim,
                            const std::string& where, PrimitiveSurface* out) {
  const auto attr = [&](const char* key) {
    const auto it = prim.attributes.find(key);
    return it == prim.attributes.end() ? -1 : it->second;
  };
  if (attr("POSITION") < 0) return corrupt(where + ": has no POSITION");
  std::vector<double> pos, nrm, tan, uv, uv1, color, idx;
  int color_components = 4;
  Status s =
      readAccessor(m, attr("POSITION"), {TINYGLTF_TYPE_VEC3}, kFloat, where + " POSITION", &pos);
  const size_t nv = pos.size() / 3;
  const auto same_count = [&](const std::vector<double>& v, size_t comps, const char* what) {
    return v.size() == nv * comps ? Status::ok()
                                  : corrupt(strCat(where, ": ", what, " has ", v.size() / comps,
                                                   " elements for ", nv, " positions"));
  };
  if (s.isOk() && attr("NORMAL") >= 0) {
    s = readAccessor(m, attr("NORMAL"), {TINYGLTF_TYPE_VEC3}, kFloat, where + " NORMAL", &nrm);
    if (s.isOk()) s = same_count(nrm, 3, "NORMAL");
  }
  if (s.isOk() && attr("TANGENT") >= 0) {
    s = readAccessor(m, attr("TANGENT"), {TINYGLTF_TYPE_VEC4}, kFloat, where + " TANGENT", &tan);
    if (s.isOk()) s = same_count(tan, 4, "TANGENT");
  }
  if (s.isOk() && attr("TEXCOORD_0") >= 0) {
    s = readAccessor(m, attr("TEXCOORD_0"), {TINYGLTF_TYPE_VEC2}, kFloatOrNormalized,
                     where + " TEXCOORD_0", &uv);
    if (s.isOk()) s = same_count(uv, 2, "TEXCOORD_0");
  }
  if (s.isOk() && attr("TEXCOORD_1") >= 0) {
    s = readAccessor(m, attr("TEXCOORD_1"), {TINYGLTF_TYPE_VEC2}, kFloatOrNormalized,
                     where + " TEXCOORD_1", &uv1);
    if (s.isOk()) s = same_count(uv1, 2, "TEXCOORD_1");
  }
  if (s.isOk() && attr("COLOR_0") >= 0) {
    s = readAccessor(m, attr("COLOR_0"), {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4},
                     kFloatOrNormalized, where + " COLOR_0", &color, &color_components);
    if (s.isOk()) s = same_count(color, size_t(color_components), "COLOR_0");
  }
  if (s.isOk() && prim.indices >= 0)
    s = readAccessor(m, prim.indices, {TINYGLTF_TYPE_SCALAR}, kAnyInt, where + " indices", &idx);
  if (!s.isOk()) return s;
  PrimitiveSurface out_surface;
  out_surface.has_texcoords = !uv.empty();
  out_surface.has_texcoords1 = !uv1.empty();
  out_surface.has_colors = !color.empty();
  for (size_t v = 0; v < nv; ++v) {
    out_surface.positions.push_back(
        glm::vec3(glm::dvec3(pos[v * 3], pos[v * 3 + 1], pos[v * 3 + 2])));
    out_surface.normals.push_back(
        nrm.empty() ? glm::vec3(0.0f)
                    : glm::vec3(glm::dvec3(nrm[v * 3], nrm[v * 3 + 1], nrm[v * 3 + 2])));
    out_surface.texcoords.push_back(uv.empty() ? glm::vec2(0.0f)
                                               : glm::vec2(float(uv[v * 2]), float(uv[v * 2 + 1])));
    out_surface.texcoords1.push_back(
        uv1.empty() ? glm::vec2(0.0f) : glm::vec2(float(uv1[v * 2]), float(uv1[v * 2 + 1])));
    glm::vec4 rgba(1.0f);
    for (size_t k = 0; k < size_t(color_components) && !color.empty(); ++k) {
      const double c = color[v * size_t(color_components) + k];
      if (c < 0.0 || c > 1.0) ++out_surface.clamped_colors;
      rgba[int(k)] = float(std::clamp(c, 0.0, 1.0));
    }
    out_surface.colors.push_back(rgba);
    if (!tan.empty())
      out_surface.tangents.push_back(glm::vec4(float(tan[v * 4]), float(tan[v * 4 + 1]),
                                               float(tan[v * 4 + 2]), float(tan[v * 4 + 3])));
  }
  if (nv == 0) {  // The caller skips it.
    *out = std::move(out_surface);
    return Status::ok();
  }
  std::vector<uint32_t>& indices = out_surface.indices;
  if (idx.empty()) {
    for (size_t v = 0; v < nv; ++v) indices.push_back(uint32_t(v));
  } else {
    for (double i : idx) {
      if (i >= double(nv)) return corrupt(strCat(where, ": index ", i, " is not below ", nv));
      indices.push_back(uint32_t(i));
    }
  }
  if (indices.size() % 3 != 0)
    return corrupt(strCat(where, ": ", indices.size(), " indices are not triangles"));
  if (nrm.empty()) {  // Smooth normals, area weighted.
    std::vector<glm::vec3>& p = out_surface.positions;
    std::vector<glm::vec3>& n = out_surface.normals;
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
      const uint32_t a = indices[t], b = indices[t + 1], d = indices[t + 2];
      const glm::vec3 fn = glm::cross(p[b] - p[a], p[d] - p[a]);
      n[a] += fn;
      n[b] += fn;
      n[d] += fn;
    }
    for (glm::vec3& v : n) {
      const float len = glm::length(v);
      v = len > 0.0f ? v / len : glm::vec3(0, 1, 0);
    }
    out_surface.generated_normals = true;
  }
  *out = std::move(out_surface);
  return Status::ok();
}

Status convertMeshes(const tinygltf::Model& m, const SkinBinding& binding, bool keep_morph_targets,
                     GltfImportReport* report, Character* c, std::vector<ImportedPrimitive>* out,
                     std::vector<WideVertex>* wide, std::vector<NodeMorphTargets>* node_targets) {
  std::vector<std::string>& warnings = report->warnings;
  const int skin_index = binding.skin_index;
  const std::vector<int32_t>& node_to_joint = binding.node_to_joint;
  const size_t node_count = m.nodes.size();
  // ---- Meshes: every triangle primitive of every node skinned by this skin, and of every node
  // no skin moves (a rigid part, bound wholly to its node's joint).
  std::vector<ImportedPrimitive>& primitives = *out;
  primitives.clear();
  bool all_tangents = true;
  bool any_texcoords1 = false, any_colors = false;
  std::vector<std::vector<glm::vec4>> tangent_parts;
  node_targets->assign(node_count, NodeMorphTargets());
  for (size_t n = 0; n < node_count; ++n) {
    const tinygltf::Node& node = m.nodes[n];
    if (node.mesh < 0) continue;
    if (node.skin >= 0 && node.skin != skin_index) {
      warnings.push_back(strCat("node '", node.name, "' uses another skin: skipped"));
      continue;
    }
    // Its joint when rigid; where it rests then: the inverse of the joint's inverse bind.
    const int32_t rigid_joint = node.skin < 0 ? node_to_joint[n] : -1;
    const glm::dmat4 rest =
        rigid_joint >= 0
            ? glm::inverse(glm::dmat4(c->skeleton.inverse_bind_matrices[size_t(rigid_joint)]))
            : glm::dmat4(1.0);
    if (size_t(node.mesh) >= m.meshes.size())
      return corrupt(strCat("node ", n, " names mesh ", node.mesh, ", which does not exist"));
    const tinygltf::Mesh& mesh = m.meshes[size_t(node.mesh)];
    const std::string base = !mesh.name.empty() ? mesh.name : !node.name.empty() ? node.name
                                                                                 : strCat("mesh", node.mesh);
    NodeMorphTargets& targets = (*node_targets)[n];
    if (keep_morph_targets) {
      const Status ts = beginNodeMorphTargets(m, n, strCat("mesh '", base, "'"), c, &targets);
      if (!ts.isOk()) return ts;
    } else if (!mesh.primitives.empty() && !mesh.primitives.front().targets.empty()) {
      const size_t count = mesh.primitives.front().targets.size();
      report->dropped_morph_targets += uint32_t(count);
      warnings.push_back(strCat("mesh '", base, "': ", count,
                                " morph targets dropped (GltfImportDesc::keep_morph_targets)"));
    }
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& prim = mesh.primitives[p];
      const std::string where = strCat("mesh '", base, "' primitive ", p);
      if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
        warnings.push_back(where + ": not a triangle list: skipped");
        continue;
      }
      const auto attr = [&](const char* key) {
        const auto it = prim.attributes.find(key);
        return it == prim.attributes.end() ? -1 : it->second;
      };
      if (attr("POSITION") < 0) return corrupt(where + ": has no POSITION");
      if (rigid_joint < 0 && (attr("JOINTS_0") < 0 || attr("WEIGHTS_0") < 0))
        return corrupt(where + ": is skinned but has no JOINTS_0/WEIGHTS_0");
      PrimitiveSurface surface;
      Status s = readPrimitiveSurface(m, prim, where, &surface);
      std::vector<PrimitiveMorphDeltas> deltas;
      if (s.isOk() && targets.count > 0)
        s = readPrimitiveMorphDeltas(m, prim, where, surface.positions.size(), &deltas);
      if (s.isOk() && rigid_joint >= 0) {
        placeMorphDeltas(rest, surface, &deltas);
        placeSurface(rest, &surface);
      }
      const size_t nv = surface.positions.size();
      const auto same_count = [&](const std::vector<double>& v, size_t comps, const char* what) {
        return v.size() == nv * comps ? Status::ok()
                                      : corrupt(strCat(where, ": ", what, " has ", v.size() / comps,
                                                       " elements for ", nv, " positions"));
      };
      std::vector<double> j0, w0, j1, w1;
      const std::vector<int> joint_types = {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                            TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
      const std::vector<int> weight_types = {TINYGLTF_COMPONENT_TYPE_FLOAT,
                                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
      const bool skinned = rigid_joint < 0;  // A rigid part's JOINTS and WEIGHTS are unused.
      if (s.isOk() && skinned)
        s = readAccessor(m, attr("JOINTS_0"), {TINYGLTF_TYPE_VEC4}, joint_types,
                         where + " JOINTS_0", &j0);
      if (s.isOk() && skinned) s = same_count(j0, 4, "JOINTS_0");
      if (s.isOk() && skinned)
        s = readAccessor(m, attr("WEIGHTS_0"), {TINYGLTF_TYPE_VEC4}, weight_types,
                         where + " WEIGHTS_0", &w0);
      if (s.isOk() && skinned) s = same_count(w0, 4, "WEIGHTS_0");
      const bool second = skinned && attr("JOINTS_1") >= 0 && attr("WEIGHTS_1") >= 0;
      if (s.isOk() && second) {
        s = readAccessor(m, attr("JOINTS_1"), {TINYGLTF_TYPE_VEC4}, joint_types, where + " JOINTS_1", &j1);
        if (s.isOk()) s = same_count(j1, 4, "JOINTS_1");
        if (s.isOk()) s = readAccessor(m, attr("WEIGHTS_1"), {TINYGLTF_TYPE_VEC4}, weight_types, where + " WEIGHTS_1", &w1);
        if (s.isOk()) s = same_count(w1, 4, "WEIGHTS_1");
      }
      if (!s.isOk()) return s;
      if (nv == 0) {
        warnings.push_back(where + ": no vertices: skipped");
        continue;
      }
      ImportedPrimitive out_prim;
      // A "_LOD<n>" suffix on the mesh name applies to all its primitives.
      const auto [mesh_group, mesh_lod] = lodName(base);
      out_prim.mesh_name = mesh_group;
      out_prim.node_name = lodName(node.name).first;
      out_prim.primitive = uint32_t(p);
      out_prim.lod = mesh_lod;
      out_prim.rigid = !skinned;
      out_prim.material = prim.material >= 0 ? uint32_t(prim.material) + 1 : 0;  // 0: default.
      if (prim.material >= 0 && size_t(prim.material) >= m.materials.size())
        return corrupt(strCat(where, ": material ", prim.material, " does not exist"));
      const uint32_t first = uint32_t(c->mesh.positions.size());
      appendMorphDeltas(deltas, first, targets, c);
      c->mesh.positions.insert(c->mesh.positions.end(), surface.positions.begin(),
                               surface.positions.end());
      c->mesh.normals.insert(c->mesh.normals.end(), surface.normals.begin(), surface.normals.end());
      c->mesh.texcoords.insert(c->mesh.texcoords.end(), surface.texcoords.begin(),
                               surface.texcoords.end());
      // Kept below only when some primitive has them (the others' are 0 and white).
      c->mesh.texcoords1.insert(c->mesh.texcoords1.end(), surface.texcoords1.begin(),
                                surface.texcoords1.end());
      c->mesh.colors.insert(c->mesh.colors.end(), surface.colors.begin(), surface.colors.end());
      any_texcoords1 = any_texcoords1 || surface.has_texcoords1;
      any_colors = any_colors || surface.has_colors;
      if (surface.clamped_colors != 0)
        warnings.push_back(
            strCat(where, ": ", surface.clamped_colors, " COLOR_0 values outside [0, 1] clamped"));
      for (size_t v = 0; v < nv && !skinned; ++v) {  // Wholly its node's.
        c->mesh.joints.push_back(glm::u16vec4(uint16_t(rigid_joint), 0, 0, 0));
        c->mesh.weights.push_back(glm::vec4(1, 0, 0, 0));
      }
      // The skin's joint nodes (a skinned node names the chosen skin).
      const std::vector<int>* skin_joints = skinned ? &binding.skin->joints : nullptr;
      for (size_t v = 0; v < nv && skinned; ++v) {
        Influence infl[8];
        size_t k = 0;
        for (int i = 0; i < 4; ++i) infl[k++] = {uint32_t(j0[v * 4 + size_t(i)]), float(w0[v * 4 + size_t(i)])};
        if (second)
          for (int i = 0; i < 4; ++i) infl[k++] = {uint32_t(j1[v * 4 + size_t(i)]), float(w1[v * 4 + size_t(i)])};
        for (size_t i = 0; i < k; ++i) {
          if (infl[i].weight == 0.0f) {
            infl[i].joint = 0;
            continue;
          }
          if (infl[i].joint >= skin_joints->size())
            return corrupt(strCat(where, ": vertex ", v, " uses joint ", infl[i].joint, " of ",
                                  skin_joints->size()));
          infl[i].joint = uint32_t(node_to_joint[size_t((*skin_joints)[infl[i].joint])]);
        }
        glm::u16vec4 joints;
        glm::vec4 weights;
        float dropped = 0.0f;
        s = reduceInfluences(Span<const Influence>(infl, k), &joints, &weights, &dropped);
        if (!s.isOk()) return corrupt(strCat(where, ": vertex ", v, ": ", s.message()));
        report->max_dropped_weight = std::max(report->max_dropped_weight, dropped);
        double raw_sum = 0.0;
        for (size_t i = 0; i < k; ++i) raw_sum += infl[i].weight;
        if (dropped > 0.0f) {  // reduceInfluences refused a zero or non-finite sum.
          WideVertex w;
          w.vertex = uint32_t(c->mesh.joints.size());
          w.dropped_weight = dropped;
          for (size_t i = 0; i < k; ++i)
            if (infl[i].weight > 0.0f)
              w.influences[w.count++] = {infl[i].joint, float(infl[i].weight / raw_sum)};
          wide->push_back(w);
        }
        if (std::fabs(raw_sum - 1.0) > kWeightSumTolerance) {
          ++report->vertices_renormalized;
          report->max_weight_correction = std::max(report->max_weight_correction, float(std::fabs(1.0 - raw_sum)));
        }
        c->mesh.joints.push_back(joints);
        c->mesh.weights.push_back(weights);
      }
      tangent_parts.push_back(std::move(surface.tangents));
      if (tangent_parts.back().empty()) all_tangents = false;
      for (uint32_t i : surface.indices) out_prim.indices.push_back(first + i);
      if (surface.generated_normals)
        warnings.push_back(where + ": no NORMAL: generated smooth normals");
      ++(skinned ? report->skinned_primitives : report->rigid_primitives);
      primitives.push_back(std::move(out_prim));
    }
  }
  if (primitives.empty())
    return {StatusCode::kUnsupported, skin_index >= 0 ? strCat("glTF: no triangle mesh uses skin ",
                                                               skin_index, " or moves with a node")
                                                      : std::string("glTF: no triangle mesh")};
  if (!any_texcoords1) c->mesh.texcoords1.clear();
  if (!any_colors) c->mesh.colors.clear();
  if (all_tangents)
    for (const auto& part : tangent_parts) c->mesh.tangents.insert(c->mesh.tangents.end(), part.begin(), part.end());
  else if (!tangent_parts.empty() && std::any_of(tangent_parts.begin(), tangent_parts.end(),
                                                 [](const auto& t) { return !t.empty(); }))
    warnings.push_back(
        "some primitives have TANGENT and others not: tangents dropped (generated where a normal "
        "map needs them)");
  finishMorphTargets(report, c);
  return Status::ok();
}

}  // namespace si::detail
