// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// glTF 2.0 import (Khronos glTF 2.0 specification, "Skins", "Animations", "Accessors").
// tinygltf parses; every read below checks its range first, in 64-bit arithmetic.
#include "si/gltf/gltf_import.h"

#include <tiny_gltf.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>

#include "core/str_cat.h"
#include "si/gltf/asset_path.h"

namespace si {
using detail::strCat;

namespace {

constexpr uint64_t kMaxElements = uint64_t(1) << 26;  // 67M elements per accessor.

Status corrupt(const std::string& what) { return {StatusCode::kCorrupt, "glTF: " + what}; }

// ---- File system callbacks: no path expansion, no escape from the asset's folder -----------
struct FsContext {
  std::string base_dir;
};

bool fileExists(const std::string& path, void* user) {
  const FsContext* fs = static_cast<const FsContext*>(user);
  if (fs->base_dir.empty()) return false;
  std::ifstream f(path, std::ios::binary);
  return bool(f);
}
std::string noExpansion(const std::string& path, void*) { return path; }
bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void* user) {
  const FsContext* fs = static_cast<const FsContext*>(user);
  // tinygltf joins the base folder and the (decoded) URI: the remainder must resolve inside it.
  const std::string prefix = fs->base_dir.empty() ? "" : fs->base_dir + "/";
  std::string resolved;
  if (fs->base_dir.empty() || path.compare(0, prefix.size(), prefix) != 0 ||
      !resolveAssetUri(fs->base_dir, path.substr(prefix.size()), &resolved).isOk()) {
    if (err) *err += "refused to read '" + path + "': outside the asset's folder\n";
    return false;
  }
  std::ifstream f(resolved, std::ios::binary | std::ios::ate);
  if (!f) {
    if (err) *err += "cannot read '" + resolved + "'\n";
    return false;
  }
  const std::streamoff size = f.tellg();
  if (size < 0 || uint64_t(size) > (uint64_t(1) << 31)) {
    if (err) *err += "'" + resolved + "' is too large\n";
    return false;
  }
  out->resize(size_t(size));
  f.seekg(0);
  f.read(reinterpret_cast<char*>(out->data()), size);
  return bool(f);
}
bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not supported\n";
  return false;
}

struct ImageContext {
  bool load;
  std::vector<std::string>* warnings;
};
bool loadImage(tinygltf::Image* image, const int index, std::string* err, std::string* warn,
               int req_w, int req_h, const unsigned char* bytes, int size, void* user) {
  const ImageContext* ctx = static_cast<const ImageContext*>(user);
  if (!ctx->load) return true;  // Images are optional.
  std::string e, w;
  if (!tinygltf::LoadImageData(image, index, &e, &w, req_w, req_h, bytes, size, nullptr)) {
    ctx->warnings->push_back(strCat("image ", index, " could not be decoded (", e,
                                    "): its materials keep their factor only"));
    image->image.clear();
  }
  (void)err;
  (void)warn;
  return true;
}

// ---- Accessors --------------------------------------------------------------------------
int componentSize(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

double readComponent(const uint8_t* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const int8_t v = int8_t(p[0]);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: return 0.0;
  }
}

// The bytes [offset, offset + size) of buffer view `view_index`, checked.
Status viewBytes(const tinygltf::Model& m, int view_index, uint64_t offset, uint64_t size,
                 const std::string& what, const uint8_t** out, uint64_t* view_length) {
  if (view_index < 0 || size_t(view_index) >= m.bufferViews.size())
    return corrupt(strCat(what, ": buffer view ", view_index, " does not exist"));
  const tinygltf::BufferView& v = m.bufferViews[size_t(view_index)];
  if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size())
    return corrupt(strCat(what, ": buffer view ", view_index, " names buffer ", v.buffer,
                          ", which does not exist"));
  const uint64_t buffer_size = m.buffers[size_t(v.buffer)].data.size();
  const uint64_t begin = uint64_t(v.byteOffset), length = uint64_t(v.byteLength);
  if (begin > buffer_size || length > buffer_size - begin)
    return corrupt(strCat(what, ": buffer view ", view_index, " [", begin, ", +", length,
                          ") lies outside its buffer of ", buffer_size, " bytes"));
  if (offset > length || size > length - offset)
    return corrupt(strCat(what, ": reads [", offset, ", +", size, ") of buffer view ",
                          view_index, ", which has ", length, " bytes"));
  *out = m.buffers[size_t(v.buffer)].data.data() + begin;
  if (view_length) *view_length = length;
  return Status::ok();
}

// Reads accessor `index` into `out` (count x components doubles), checking its type and every
// range; sparse accessors are applied.
Status readAccessor(const tinygltf::Model& m, int index, const std::vector<int>& types,
                    const std::vector<int>& component_types, const std::string& what,
                    std::vector<double>* out, int* components_out = nullptr) {
  if (index < 0 || size_t(index) >= m.accessors.size())
    return corrupt(strCat(what, ": accessor ", index, " does not exist"));
  const tinygltf::Accessor& a = m.accessors[size_t(index)];
  const std::string name = strCat(what, " (accessor ", index, ")");
  if (std::find(types.begin(), types.end(), a.type) == types.end())
    return corrupt(strCat(name, ": unexpected type ", a.type));
  if (std::find(component_types.begin(), component_types.end(), a.componentType) ==
      component_types.end())
    return corrupt(strCat(name, ": unexpected component type ", a.componentType));
  const int comps = tinygltf::GetNumComponentsInType(uint32_t(a.type));
  const int csize = componentSize(a.componentType);
  if (comps <= 0 || csize <= 0) return corrupt(name + ": invalid type");
  const uint64_t count = a.count;
  if (count > kMaxElements) return corrupt(strCat(name, ": count ", count, " is too large"));
  const uint64_t elem = uint64_t(comps) * uint64_t(csize);
  std::vector<double> values(size_t(count * uint64_t(comps)), 0.0);
  if (a.bufferView >= 0 && count > 0) {
    const tinygltf::BufferView& v = m.bufferViews.size() > size_t(a.bufferView)
                                        ? m.bufferViews[size_t(a.bufferView)]
                                        : tinygltf::BufferView();
    const uint64_t stride = v.byteStride ? uint64_t(v.byteStride) : elem;
    if (stride < elem || stride > 1024)
      return corrupt(strCat(name, ": byte stride ", stride, " does not fit elements of ", elem,
                            " bytes"));
    const uint64_t span = stride * (count - 1) + elem;
    const uint8_t* base = nullptr;
    Status s = viewBytes(m, a.bufferView, uint64_t(a.byteOffset), span, name, &base, nullptr);
    if (!s.isOk()) return s;
    base += a.byteOffset;
    for (uint64_t i = 0; i < count; ++i)
      for (int c = 0; c < comps; ++c)
        values[size_t(i * comps + c)] =
            readComponent(base + i * stride + uint64_t(c) * csize, a.componentType, a.normalized);
  } else if (!a.sparse.isSparse && count > 0) {
    return corrupt(name + ": has neither a buffer view nor sparse values");
  }
  if (a.sparse.isSparse) {
    const uint64_t n = uint64_t(std::max(a.sparse.count, 0));
    if (a.sparse.count <= 0 || n > count)
      return corrupt(strCat(name, ": sparse count ", a.sparse.count, " out of range"));
    const int icomp = a.sparse.indices.componentType;
    const int isize = componentSize(icomp);
    if (icomp != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        icomp != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        icomp != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      return corrupt(name + ": sparse indices must be unsigned integers");
    const uint8_t* ib = nullptr;
    const uint8_t* vb = nullptr;
    if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
      return corrupt(name + ": negative sparse byte offset");
    Status s = viewBytes(m, a.sparse.indices.bufferView, uint64_t(a.sparse.indices.byteOffset),
                         n * uint64_t(isize), name + " sparse indices", &ib, nullptr);
    if (s.isOk())
      s = viewBytes(m, a.sparse.values.bufferView, uint64_t(a.sparse.values.byteOffset), n * elem,
                    name + " sparse values", &vb, nullptr);
    if (!s.isOk()) return s;
    ib += a.sparse.indices.byteOffset;
    vb += a.sparse.values.byteOffset;
    for (uint64_t k = 0; k < n; ++k) {
      const uint64_t target = uint64_t(readComponent(ib + k * isize, icomp, false));
      if (target >= count)
        return corrupt(strCat(name, ": sparse index ", target, " is not below ", count));
      for (int c = 0; c < comps; ++c)
        values[size_t(target * comps + c)] =
            readComponent(vb + k * elem + uint64_t(c) * csize, a.componentType, a.normalized);
    }
  }
  for (double v : values)
    if (!std::isfinite(v)) return corrupt(name + ": contains NaN or infinity");
  if (components_out) *components_out = comps;
  *out = std::move(values);
  return Status::ok();
}

const std::vector<int> kFloat = {TINYGLTF_COMPONENT_TYPE_FLOAT};
const std::vector<int> kAnyInt = {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT};
const std::vector<int> kFloatOrNormalized = {
    TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
    TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_COMPONENT_TYPE_BYTE,
    TINYGLTF_COMPONENT_TYPE_SHORT};

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

struct Primitive {
  std::string name;
  uint32_t lod = 0;
  uint32_t material = 0;
  std::vector<uint32_t> indices;  // Into the character's vertex arrays.
};

Status convert(const tinygltf::Model& m, const GltfImportDesc& desc, Character* out,
               GltfImportReport* report) {
  std::vector<std::string>& warnings = report->warnings;
  // ---- The skin.
  if (m.skins.empty()) return {StatusCode::kUnsupported, "glTF: the asset has no skin"};
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
    } else {
      return {StatusCode::kAmbiguous, strCat("glTF: the asset has ", m.skins.size(),
                                             " skins; choose one by index or name")};
    }
  }
  const tinygltf::Skin& skin = m.skins[size_t(skin_index)];
  if (skin.joints.empty()) return corrupt(strCat("skin ", skin_index, " has no joints"));
  report->skin_joints = uint32_t(skin.joints.size());
  const size_t node_count = m.nodes.size();
  std::vector<int> parent(node_count, -1);
  for (size_t n = 0; n < node_count; ++n)
    for (int c : m.nodes[n].children) {
      if (c < 0 || size_t(c) >= node_count)
        return corrupt(strCat("node ", n, " has child ", c, ", which does not exist"));
      if (parent[size_t(c)] != -1)
        return corrupt(strCat("node ", c, " has two parents"));
      parent[size_t(c)] = int(n);
    }
  // The skeleton: the skin's joints and every ancestor of them, parents first.
  std::set<int> members;
  for (int j : skin.joints) {
    if (j < 0 || size_t(j) >= node_count)
      return corrupt(strCat("skin ", skin_index, " names joint node ", j, ", which does not exist"));
    size_t steps = 0;
    for (int n = j; n >= 0; n = parent[size_t(n)]) {
      if (++steps > node_count) return corrupt(strCat("the node hierarchy has a cycle at node ", j));
      members.insert(n);
    }
  }
  std::vector<std::pair<size_t, int>> by_depth;
  for (int n : members) {
    size_t depth = 0;
    for (int p = parent[size_t(n)]; p >= 0; p = parent[size_t(p)]) ++depth;
    by_depth.push_back({depth, n});
  }
  std::sort(by_depth.begin(), by_depth.end());
  std::vector<int32_t> node_to_joint(node_count, -1);
  Character c;
  for (const auto& [depth, n] : by_depth) {
    (void)depth;
    node_to_joint[size_t(n)] = int32_t(c.skeleton.parents.size());
    const tinygltf::Node& node = m.nodes[size_t(n)];
    c.skeleton.joint_names.push_back(node.name.empty() ? strCat("node", n) : node.name);
    c.skeleton.parents.push_back(parent[size_t(n)] >= 0 ? node_to_joint[size_t(parent[size_t(n)])] : -1);
    c.skeleton.rest_pose.push_back(nodeTransform(node, &warnings));
    c.skeleton.inverse_bind_matrices.push_back(glm::mat4(1.0f));
  }
  if (skin.inverseBindMatrices >= 0) {
    std::vector<double> ibm;
    Status s = readAccessor(m, skin.inverseBindMatrices, {TINYGLTF_TYPE_MAT4}, kFloat,
                            strCat("skin ", skin_index, " inverse bind matrices"), &ibm);
    if (!s.isOk()) return s;
    if (ibm.size() != skin.joints.size() * 16)
      return corrupt(strCat("skin ", skin_index, ": ", ibm.size() / 16, " inverse bind matrices for ",
                            skin.joints.size(), " joints"));
    for (size_t k = 0; k < skin.joints.size(); ++k) {
      glm::mat4 mat;
      for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) mat[col][row] = float(ibm[k * 16 + size_t(col * 4 + row)]);
      c.skeleton.inverse_bind_matrices[size_t(node_to_joint[size_t(skin.joints[k])])] = mat;
    }
  }

  // ---- Meshes: every triangle primitive of every node skinned by this skin.
  std::vector<Primitive> primitives;
  bool all_tangents = true;
  std::vector<std::vector<glm::vec4>> tangent_parts;
  for (size_t n = 0; n < node_count; ++n) {
    const tinygltf::Node& node = m.nodes[n];
    if (node.mesh < 0) continue;
    if (node.skin != skin_index) {
      if (node.skin >= 0) warnings.push_back(strCat("node '", node.name, "' uses another skin: skipped"));
      continue;
    }
    if (size_t(node.mesh) >= m.meshes.size())
      return corrupt(strCat("node ", n, " names mesh ", node.mesh, ", which does not exist"));
    const tinygltf::Mesh& mesh = m.meshes[size_t(node.mesh)];
    const std::string base = !mesh.name.empty() ? mesh.name : !node.name.empty() ? node.name
                                                                                 : strCat("mesh", node.mesh);
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
      if (attr("JOINTS_0") < 0 || attr("WEIGHTS_0") < 0)
        return corrupt(where + ": is skinned but has no JOINTS_0/WEIGHTS_0");
      std::vector<double> pos, nrm, tan, uv, j0, w0, j1, w1, idx;
      Status s = readAccessor(m, attr("POSITION"), {TINYGLTF_TYPE_VEC3}, kFloat, where + " POSITION", &pos);
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
      const std::vector<int> joint_types = {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                            TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
      const std::vector<int> weight_types = {TINYGLTF_COMPONENT_TYPE_FLOAT,
                                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
      if (s.isOk()) s = readAccessor(m, attr("JOINTS_0"), {TINYGLTF_TYPE_VEC4}, joint_types, where + " JOINTS_0", &j0);
      if (s.isOk()) s = same_count(j0, 4, "JOINTS_0");
      if (s.isOk()) s = readAccessor(m, attr("WEIGHTS_0"), {TINYGLTF_TYPE_VEC4}, weight_types, where + " WEIGHTS_0", &w0);
      if (s.isOk()) s = same_count(w0, 4, "WEIGHTS_0");
      const bool second = attr("JOINTS_1") >= 0 && attr("WEIGHTS_1") >= 0;
      if (s.isOk() && second) {
        s = readAccessor(m, attr("JOINTS_1"), {TINYGLTF_TYPE_VEC4}, joint_types, where + " JOINTS_1", &j1);
        if (s.isOk()) s = same_count(j1, 4, "JOINTS_1");
        if (s.isOk()) s = readAccessor(m, attr("WEIGHTS_1"), {TINYGLTF_TYPE_VEC4}, weight_types, where + " WEIGHTS_1", &w1);
        if (s.isOk()) s = same_count(w1, 4, "WEIGHTS_1");
      }
      if (s.isOk() && prim.indices >= 0)
        s = readAccessor(m, prim.indices, {TINYGLTF_TYPE_SCALAR}, kAnyInt, where + " indices", &idx);
      if (!s.isOk()) return s;
      if (nv == 0) {
        warnings.push_back(where + ": no vertices: skipped");
        continue;
      }
      Primitive out_prim;
      const auto [group, lod] = lodName(mesh.primitives.size() > 1 ? strCat(base, "_p", p) : base);
      // A "_LOD<n>" suffix on the mesh name applies to all its primitives.
      const auto [mesh_group, mesh_lod] = lodName(base);
      out_prim.name = mesh.primitives.size() > 1 ? strCat(mesh_group, "_p", p) : group;
      out_prim.lod = mesh.primitives.size() > 1 ? mesh_lod : lod;
      out_prim.material = prim.material >= 0 ? uint32_t(prim.material) + 1 : 0;  // 0: default.
      if (prim.material >= 0 && size_t(prim.material) >= m.materials.size())
        return corrupt(strCat(where, ": material ", prim.material, " does not exist"));
      const uint32_t first = uint32_t(c.mesh.positions.size());
      for (size_t v = 0; v < nv; ++v) {
        c.mesh.positions.push_back(glm::vec3(glm::dvec3(pos[v * 3], pos[v * 3 + 1], pos[v * 3 + 2])));
        c.mesh.normals.push_back(nrm.empty() ? glm::vec3(0.0f)
                                             : glm::vec3(glm::dvec3(nrm[v * 3], nrm[v * 3 + 1], nrm[v * 3 + 2])));
        c.mesh.texcoords.push_back(uv.empty() ? glm::vec2(0.0f) : glm::vec2(float(uv[v * 2]), float(uv[v * 2 + 1])));
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
          if (infl[i].joint >= skin.joints.size())
            return corrupt(strCat(where, ": vertex ", v, " uses joint ", infl[i].joint, " of ",
                                  skin.joints.size()));
          infl[i].joint = uint32_t(node_to_joint[size_t(skin.joints[infl[i].joint])]);
        }
        glm::u16vec4 joints;
        glm::vec4 weights;
        float dropped = 0.0f;
        s = reduceInfluences(Span<const Influence>(infl, k), &joints, &weights, &dropped);
        if (!s.isOk()) return corrupt(strCat(where, ": vertex ", v, ": ", s.message()));
        report->max_dropped_weight = std::max(report->max_dropped_weight, dropped);
        double raw_sum = 0.0;
        for (size_t i = 0; i < k; ++i) raw_sum += infl[i].weight;
        if (std::fabs(raw_sum - 1.0) > kWeightSumTolerance) {
          ++report->vertices_renormalized;
          report->max_weight_correction = std::max(report->max_weight_correction, float(std::fabs(1.0 - raw_sum)));
        }
        c.mesh.joints.push_back(joints);
        c.mesh.weights.push_back(weights);
      }
      tangent_parts.emplace_back();
      if (tan.empty()) {
        all_tangents = false;
      } else {
        for (size_t v = 0; v < nv; ++v)
          tangent_parts.back().push_back(glm::vec4(float(tan[v * 4]), float(tan[v * 4 + 1]),
                                                   float(tan[v * 4 + 2]), float(tan[v * 4 + 3])));
      }
      if (idx.empty()) {
        for (size_t v = 0; v < nv; ++v) out_prim.indices.push_back(first + uint32_t(v));
      } else {
        for (double i : idx) {
          if (i >= double(nv)) return corrupt(strCat(where, ": index ", i, " is not below ", nv));
          out_prim.indices.push_back(first + uint32_t(i));
        }
      }
      if (out_prim.indices.size() % 3 != 0)
        return corrupt(strCat(where, ": ", out_prim.indices.size(), " indices are not triangles"));
      if (nrm.empty()) {  // Smooth normals, area weighted.
        for (size_t t = 0; t + 2 < out_prim.indices.size(); t += 3) {
          const uint32_t a = out_prim.indices[t], b = out_prim.indices[t + 1], d = out_prim.indices[t + 2];
          const glm::vec3 fn = glm::cross(c.mesh.positions[b] - c.mesh.positions[a],
                                          c.mesh.positions[d] - c.mesh.positions[a]);
          c.mesh.normals[a] += fn;
          c.mesh.normals[b] += fn;
          c.mesh.normals[d] += fn;
        }
        for (size_t v = first; v < c.mesh.normals.size(); ++v) {
          const float len = glm::length(c.mesh.normals[v]);
          c.mesh.normals[v] = len > 0.0f ? c.mesh.normals[v] / len : glm::vec3(0, 1, 0);
        }
        warnings.push_back(where + ": no NORMAL: generated smooth normals");
      }
      ++report->skinned_primitives;
      primitives.push_back(std::move(out_prim));
    }
  }
  if (primitives.empty())
    return {StatusCode::kUnsupported, strCat("glTF: no triangle mesh uses skin ", skin_index)};
  if (all_tangents)
    for (const auto& part : tangent_parts) c.mesh.tangents.insert(c.mesh.tangents.end(), part.begin(), part.end());
  else if (!tangent_parts.empty() && std::any_of(tangent_parts.begin(), tangent_parts.end(),
                                                 [](const auto& t) { return !t.empty(); }))
    warnings.push_back("some primitives have TANGENT and others not: tangents dropped");

  // Sub-meshes: primitives grouped by name, LODs ordered by their suffix.
  std::vector<std::string> order;
  std::map<std::string, std::map<uint32_t, const Primitive*>> groups;
  for (const Primitive& p : primitives) {
    if (!groups.count(p.name)) order.push_back(p.name);
    if (groups[p.name].count(p.lod))
      return corrupt(strCat("two meshes claim sub-mesh '", p.name, "' LOD ", p.lod));
    groups[p.name][p.lod] = &p;
  }
  if (order.size() > SkinnedMesh::kMaxSubMeshes)
    return {StatusCode::kLimitExceeded, strCat("glTF: ", order.size(), " sub-meshes (at most 32)")};
  for (const std::string& name : order) {
    SubMesh sm;
    sm.name = name;
    sm.material = groups[name].begin()->second->material;
    for (const auto& [lod, prim] : groups[name]) {
      (void)lod;
      IndexRange r{uint32_t(c.mesh.indices.size()), uint32_t(prim->indices.size())};
      c.mesh.indices.insert(c.mesh.indices.end(), prim->indices.begin(), prim->indices.end());
      sm.lods.push_back(r);
    }
    c.mesh.sub_meshes.push_back(sm);
  }
  // Generated LODs (meshoptimizer simplification of the index buffer; skin attributes are
  // untouched since vertices are kept).
  const bool has_lods = std::any_of(c.mesh.sub_meshes.begin(), c.mesh.sub_meshes.end(),
                                    [](const SubMesh& sm) { return sm.lods.size() > 1; });
  if (!has_lods && desc.generate_lods > 0) {
    const float ratio = desc.lod_index_ratio > 0.0f ? desc.lod_index_ratio : 0.25f;
    for (SubMesh& sm : c.mesh.sub_meshes) {
      for (uint32_t l = 0; l < desc.generate_lods; ++l) {
        const IndexRange prev = sm.lods.back();
        std::vector<uint32_t> src(c.mesh.indices.begin() + prev.first_index,
                                  c.mesh.indices.begin() + prev.first_index + prev.index_count);
        std::vector<uint32_t> dst(src.size());
        const size_t target = std::max<size_t>(3, size_t(double(src.size()) * ratio) / 3 * 3);
        float error = 0.0f;
        const size_t n = meshopt_simplify(dst.data(), src.data(), src.size(),
                                          &c.mesh.positions[0].x, c.mesh.positions.size(),
                                          sizeof(glm::vec3), target, 0.05f, 0, &error);
        if (n == 0 || n >= src.size()) break;  // Cannot simplify further.
        IndexRange r{uint32_t(c.mesh.indices.size()), uint32_t(n)};
        c.mesh.indices.insert(c.mesh.indices.end(), dst.begin(), dst.begin() + std::ptrdiff_t(n));
        sm.lods.push_back(r);
        ++report->generated_lods;
      }
    }
  }

  // ---- Materials (index 0 is a default white one for primitives without a material).
  c.materials.push_back(Material{"default", glm::vec4(1.0f), -1});
  std::map<int, int32_t> image_map;
  for (size_t i = 0; i < m.materials.size(); ++i) {
    const tinygltf::Material& mat = m.materials[i];
    Material out_mat;
    out_mat.name = mat.name;
    const auto& f = mat.pbrMetallicRoughness.baseColorFactor;
    if (f.size() == 4) out_mat.base_color_factor = glm::vec4(float(f[0]), float(f[1]), float(f[2]), float(f[3]));
    const int tex = mat.pbrMetallicRoughness.baseColorTexture.index;
    if (tex >= 0 && size_t(tex) < m.textures.size()) {
      const int src = m.textures[size_t(tex)].source;
      if (src >= 0 && size_t(src) < m.images.size() && !m.images[size_t(src)].image.empty()) {
        if (!image_map.count(src)) {
          const tinygltf::Image& im = m.images[size_t(src)];
          Image out_image;
          out_image.width = uint32_t(std::max(im.width, 0));
          out_image.height = uint32_t(std::max(im.height, 0));
          const int comps = im.component, bytes = im.bits / 8;
          const uint64_t texels = uint64_t(out_image.width) * out_image.height;
          if (comps < 1 || comps > 4 || (bytes != 1 && bytes != 2) ||
              im.image.size() != texels * uint64_t(comps) * uint64_t(bytes)) {
            warnings.push_back(strCat("image ", src, ": unexpected layout: skipped"));
          } else {
            out_image.rgba8.resize(size_t(texels) * 4);
            for (uint64_t t = 0; t < texels; ++t)
              for (int ch = 0; ch < 4; ++ch) {
                uint8_t v = ch == 3 ? 255 : 0;
                const int from = comps >= 3 ? ch : (ch < 3 ? 0 : 1);
                if (from < comps && (ch < 3 || comps == 4 || comps == 2))
                  v = im.image[size_t((t * uint64_t(comps) + uint64_t(from)) * uint64_t(bytes) + uint64_t(bytes - 1))];
                out_image.rgba8[size_t(t * 4 + uint64_t(ch))] = v;
              }
            image_map[src] = int32_t(c.images.size());
            c.images.push_back(std::move(out_image));
          }
        }
        if (image_map.count(src)) out_mat.base_color_image = image_map[src];
      }
    }
    c.materials.push_back(out_mat);
  }

  // ---- Animations.
  const LoopMode loop = desc.loop_mode == LoopMode::kDefault ? LoopMode::kLoop : desc.loop_mode;
  for (size_t ai = 0; ai < m.animations.size(); ++ai) {
    const tinygltf::Animation& anim = m.animations[ai];
    Clip clip;
    clip.name = anim.name.empty() ? strCat("animation", ai) : anim.name;
    clip.loop_mode = loop;
    clip.joint_tracks.resize(c.skeleton.jointCount());
    const std::string where = strCat("animation '", clip.name, "'");
    for (size_t ch = 0; ch < anim.channels.size(); ++ch) {
      const tinygltf::AnimationChannel& channel = anim.channels[ch];
      const std::string cw = strCat(where, " channel ", ch);
      if (channel.target_path == "weights") {
        warnings.push_back(cw + ": morph target weights are not supported: skipped");
        continue;
      }
      if (channel.target_node < 0 || size_t(channel.target_node) >= node_count)
        return corrupt(strCat(cw, ": target node ", channel.target_node, " does not exist"));
      const int32_t joint = node_to_joint[size_t(channel.target_node)];
      if (joint < 0) {
        warnings.push_back(strCat(cw, ": targets node '", m.nodes[size_t(channel.target_node)].name,
                                  "' outside the skeleton: skipped"));
        continue;
      }
      if (channel.sampler < 0 || size_t(channel.sampler) >= anim.samplers.size())
        return corrupt(strCat(cw, ": sampler ", channel.sampler, " does not exist"));
      const tinygltf::AnimationSampler& sampler = anim.samplers[size_t(channel.sampler)];
      Interpolation interp = Interpolation::kLinear;
      if (sampler.interpolation == "STEP") interp = Interpolation::kStep;
      else if (sampler.interpolation == "CUBICSPLINE") interp = Interpolation::kCubicSpline;
      else if (!sampler.interpolation.empty() && sampler.interpolation != "LINEAR")
        return corrupt(strCat(cw, ": unknown interpolation '", sampler.interpolation, "'"));
      std::vector<double> times, values;
      Status s = readAccessor(m, sampler.input, {TINYGLTF_TYPE_SCALAR}, kFloat, cw + " input", &times);
      if (!s.isOk()) return s;
      const bool rotation = channel.target_path == "rotation";
      if (!rotation && channel.target_path != "translation" && channel.target_path != "scale") {
        warnings.push_back(strCat(cw, ": unknown target path '", channel.target_path, "': skipped"));
        continue;
      }
      s = readAccessor(m, sampler.output, {rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3},
                       rotation ? kFloatOrNormalized : kFloat, cw + " output", &values);
      if (!s.isOk()) return s;
      const size_t comps = rotation ? 4 : 3, per_key = interp == Interpolation::kCubicSpline ? 3 : 1;
      if (values.size() != times.size() * comps * per_key)
        return corrupt(strCat(cw, ": ", values.size() / comps, " output values for ", times.size(),
                              " key times"));
      for (size_t k = 0; k < times.size(); ++k) {
        if (times[k] < 0.0 || (k > 0 && !(times[k] > times[k - 1])))
          return corrupt(strCat(cw, ": key times not increasing (or negative) at key ", k));
        clip.duration_seconds = std::max(clip.duration_seconds, float(times[k]));
      }
      JointTracks& jt = clip.joint_tracks[size_t(joint)];
      const auto fill = [&](auto& track) {
        if (!track.empty()) {
          warnings.push_back(cw + ": a second channel for the same joint and path: skipped");
          return;
        }
        track.interpolation = interp;
        for (double t : times) track.times_seconds.push_back(float(t));
      };
      if (rotation) {
        fill(jt.rotation);
        if (jt.rotation.values.empty() && !jt.rotation.times_seconds.empty())
          for (size_t v = 0; v < values.size() / 4; ++v)
            jt.rotation.values.push_back(glm::quat(float(values[v * 4 + 3]), float(values[v * 4]),
                                                   float(values[v * 4 + 1]), float(values[v * 4 + 2])));
      } else {
        Vec3Track& track = channel.target_path == "translation" ? jt.translation : jt.scale;
        fill(track);
        if (track.values.empty() && !track.times_seconds.empty())
          for (size_t v = 0; v < values.size() / 3; ++v)
            track.values.push_back(glm::vec3(float(values[v * 3]), float(values[v * 3 + 1]),
                                             float(values[v * 3 + 2])));
      }
    }
    c.clips.push_back(std::move(clip));
  }

  WeightNormalizationReport wr;
  Status s = normalizeWeights(c.mesh, &wr);
  if (!s.isOk()) return corrupt(s.message());
  c.name = m.scenes.empty() || m.defaultScene < 0 || size_t(m.defaultScene) >= m.scenes.size()
               ? "gltf" : m.scenes[size_t(m.defaultScene)].name;
  s = c.validate();
  if (!s.isOk()) return s;
  *out = std::move(c);
  return Status::ok();
}

Status importImpl(Span<const uint8_t> bytes, const std::string& base_dir, const GltfImportDesc& desc,
                  Character* out, GltfImportReport* report) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "importGltf: out is null"};
  GltfImportReport local;
  GltfImportReport& r = report ? *report : local;
  r = GltfImportReport();
  if (bytes.size() > (size_t(1) << 31))
    return {StatusCode::kLimitExceeded, "glTF: the file is larger than 2 GiB"};
  tinygltf::TinyGLTF loader;
  FsContext fs{base_dir};
  loader.SetFsCallbacks({&fileExists, &noExpansion, &readWholeFile, &refuseWrite, &fs});
  ImageContext images{desc.load_images, &r.warnings};
  loader.SetImageLoader(&loadImage, &images);
  tinygltf::Model model;
  std::string err, warn;
  bool ok;
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                     base_dir);
  } else {
    ok = loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                    unsigned(bytes.size()), base_dir);
  }
  if (!warn.empty()) r.warnings.push_back("tinygltf: " + warn);
  if (!ok) return corrupt("cannot parse: " + (err.empty() ? std::string("unknown error") : err));
  return convert(model, desc, out, &r);
}

}  // namespace

Status importGltfMemory(Span<const uint8_t> bytes, const std::string& base_dir,
                        const GltfImportDesc& desc, Character* out, GltfImportReport* report) {
  return importImpl(bytes, base_dir, desc, out, report);
}

Status importGltfFile(const std::string& path, const GltfImportDesc& desc, Character* out,
                      GltfImportReport* report) {
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) return {StatusCode::kIo, strCat("glTF: cannot open '", path, "'")};
  const std::streamoff size = f.tellg();
  if (size < 0 || uint64_t(size) > (uint64_t(1) << 31))
    return {StatusCode::kIo, strCat("glTF: cannot read '", path, "'")};
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  f.seekg(0);
  f.read(reinterpret_cast<char*>(bytes.data()), size);
  if (!f) return {StatusCode::kIo, strCat("glTF: cannot read '", path, "'")};
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : path.substr(0, slash);
  return importImpl(bytes, dir, desc, out, report);
}

}  // namespace si
