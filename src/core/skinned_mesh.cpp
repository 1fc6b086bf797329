// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/skinned_mesh.h"

#include <algorithm>
#include <cmath>

#include "core/str_cat.h"
#include "core/vertex_checks.h"
#include "si/core/transform.h"

namespace si {
using detail::strCat;

size_t SkinnedMesh::maxLodCount() const {
  size_t n = 0;
  for (const SubMesh& s : sub_meshes) n = std::max(n, s.lods.size());
  return n;
}

size_t SkinnedMesh::triangleCount(size_t sub_mesh, size_t lod) const {
  if (sub_mesh >= sub_meshes.size() || sub_meshes[sub_mesh].lods.empty()) return 0;
  const auto& lods = sub_meshes[sub_mesh].lods;
  return lods[std::min(lod, lods.size() - 1)].index_count / 3;
}

Status SkinnedMesh::validate(size_t joint_count) const {
  const size_t n = positions.size();
  if (n == 0) return {StatusCode::kInvalidArgument, "mesh: positions is empty"};
  const auto count = [&](const char* what, size_t c, bool optional) -> Status {
    if (c == n || (optional && c == 0)) return Status::ok();
    return {StatusCode::kCountMismatch, strCat("mesh: ", what, " has ", c, " elements for ", n,
                                               " vertices", optional ? " (or none)" : "")};
  };
  for (Status s :
       {count("normals", normals.size(), false), count("joints", joints.size(), false),
        count("weights", weights.size(), false), count("tangents", tangents.size(), true),
        count("texcoords", texcoords.size(), true), count("texcoords1", texcoords1.size(), true),
        count("colors", colors.size(), true), count("joints1", joints1.size(), true),
        count("weights1", weights1.size(), true),
        count("vertex_materials", vertex_materials.size(), true)})
    if (!s.isOk()) return s;
  if (joints1.empty() != weights1.empty())
    return {StatusCode::kCountMismatch,
            strCat("mesh: joints1 has ", joints1.size(), " elements and weights1 ", weights1.size(),
                   ": both or neither")};
  const size_t influences = influenceCount();

  for (size_t v = 0; v < n; ++v) {
    if (!isFinite(positions[v]))
      return {StatusCode::kNotFinite, strCat("mesh: position ", v, " is not finite")};
    if (!isFinite(normals[v]))
      return {StatusCode::kNotFinite, strCat("mesh: normal ", v, " is not finite")};
    if (!tangents.empty() && !isFinite(tangents[v]))
      return {StatusCode::kNotFinite, strCat("mesh: tangent ", v, " is not finite")};
    if (!texcoords.empty() && !detail::isFinite2(texcoords[v]))
      return {StatusCode::kNotFinite, strCat("mesh: texcoord ", v, " is not finite")};
    if (!texcoords1.empty() && !detail::isFinite2(texcoords1[v]))
      return {StatusCode::kNotFinite, strCat("mesh: texcoord1 ", v, " is not finite")};
    if (!colors.empty() && !isFinite(colors[v]))
      return {StatusCode::kNotFinite, strCat("mesh: color ", v, " is not finite")};
    if (!colors.empty() && !detail::inUnitRange(colors[v]))
      return {StatusCode::kOutOfRange, strCat("mesh: color ", v, " is outside [0, 1]")};
    if (!isFinite(weights[v]))
      return {StatusCode::kNotFinite, strCat("mesh: weights ", v, " not finite")};
    if (!weights1.empty() && !isFinite(weights1[v]))
      return {StatusCode::kNotFinite, strCat("mesh: weights1 ", v, " not finite")};
    float sum = 0.0f;
    for (size_t i = 0; i < influences; ++i) {
      const Influence in = influence(v, i);
      if (in.weight < 0.0f)
        return {StatusCode::kOutOfRange, strCat("mesh: vertex ", v, " weight ", i, " is negative")};
      sum += in.weight;
      if (in.joint >= joint_count)
        return {StatusCode::kOutOfRange, strCat("mesh: vertex ", v, " joint index ", in.joint,
                                                " is not below the joint count ", joint_count)};
    }
    if (std::fabs(sum - 1.0f) > kWeightSumTolerance)
      return {StatusCode::kInvalidArgument,
              strCat("mesh: vertex ", v, " weights sum to ", sum,
                     ", not 1 (call normalizeWeights to renormalize)")};
  }

  if (indices.size() % 3 != 0)
    return {StatusCode::kInvalidArgument,
            strCat("mesh: index count ", indices.size(), " is not a multiple of 3")};
  for (size_t i = 0; i < indices.size(); ++i)
    if (indices[i] >= n)
      return {StatusCode::kOutOfRange, strCat("mesh: index ", i, " (", indices[i],
                                              ") is not below the vertex count ", n)};

  if (sub_meshes.empty() || sub_meshes.size() > kMaxSubMeshes)
    return {StatusCode::kLimitExceeded, strCat("mesh: has ", sub_meshes.size(),
                                               " sub-meshes; needs 1 to ", kMaxSubMeshes)};
  for (size_t s = 0; s < sub_meshes.size(); ++s) {
    const SubMesh& sm = sub_meshes[s];
    if (sm.lods.empty())
      return {StatusCode::kOutOfRange, strCat("mesh: sub-mesh ", s, " '", sm.name, "' has no LOD")};
    for (size_t l = 0; l < sm.lods.size(); ++l) {
      const IndexRange& r = sm.lods[l];
      // Past LOD 0 a level may be empty: the part is not drawn there (si::buildPartLods).
      const bool ok = (r.index_count > 0 || l > 0) && r.index_count % 3 == 0 &&
                      r.first_index % 3 == 0 &&
                      size_t(r.first_index) <= indices.size() &&
                      size_t(r.index_count) <= indices.size() - r.first_index;
      if (!ok)
        return {StatusCode::kOutOfRange,
                strCat("mesh: sub-mesh ", s, " '", sm.name, "' LOD ", l, " range [",
                       r.first_index, ", +", r.index_count,
                       ") must be triangle aligned, inside the ", indices.size(),
                       " indices and, at LOD 0, non-empty")};
    }
    if (!sm.lod_error_units.empty() && sm.lod_error_units.size() != sm.lods.size())
      return {StatusCode::kCountMismatch,
              strCat("mesh: sub-mesh ", s, " '", sm.name, "' has ", sm.lod_error_units.size(),
                     " LOD errors for ", sm.lods.size(), " LODs")};
    for (size_t l = 0; l < sm.lod_error_units.size(); ++l)
      if (!std::isfinite(sm.lod_error_units[l]) || sm.lod_error_units[l] < 0.0f)
        return {StatusCode::kOutOfRange, strCat("mesh: sub-mesh ", s, " '", sm.name, "' LOD ", l,
                                                " error must be finite and >= 0")};
  }
  return validateMorphTargets(morph_targets, n, !tangents.empty());
}

Status normalizeWeights(SkinnedMesh& mesh, WeightNormalizationReport* report) {
  const bool second = !mesh.weights1.empty() && mesh.weights1.size() == mesh.weights.size();
  const auto negative = [](const glm::vec4& w) { return w.x < 0 || w.y < 0 || w.z < 0 || w.w < 0; };
  const auto sumOf = [&](size_t v) {
    double sum =
        double(mesh.weights[v].x) + mesh.weights[v].y + mesh.weights[v].z + mesh.weights[v].w;
    if (second)
      sum +=
          double(mesh.weights1[v].x) + mesh.weights1[v].y + mesh.weights1[v].z + mesh.weights1[v].w;
    return sum;
  };
  // Check every vertex first so that a failure leaves the mesh untouched.
  for (size_t v = 0; v < mesh.weights.size(); ++v) {
    const glm::vec4& w = mesh.weights[v];
    if (!isFinite(w) || negative(w) ||
        (second && (!isFinite(mesh.weights1[v]) || negative(mesh.weights1[v]))))
      return {StatusCode::kInvalidArgument,
              strCat("mesh: vertex ", v, " has negative or non-finite weights")};
    if (!(sumOf(v) > 1e-6))
      return {StatusCode::kInvalidArgument,
              strCat("mesh: vertex ", v, " weights sum to zero; it is bound to no joint")};
  }
  WeightNormalizationReport r;
  for (size_t v = 0; v < mesh.weights.size(); ++v) {
    const double sum = sumOf(v);
    const float correction = static_cast<float>(std::fabs(1.0 - sum));
    if (correction == 0.0f) continue;
    mesh.weights[v] = glm::vec4(glm::dvec4(mesh.weights[v]) / sum);
    if (second) mesh.weights1[v] = glm::vec4(glm::dvec4(mesh.weights1[v]) / sum);
    ++r.vertices_changed;
    if (correction > r.max_correction) {
      r.max_correction = correction;
      r.max_correction_vertex = v;
    }
  }
  if (report != nullptr) *report = r;
  return Status::ok();
}

namespace {
// n weights as unorm16 summing to exactly 65535: each rounded, then the largest (the first of
// equals) absorbs the difference.
void quantize(const float* w, uint16_t* q, int n) {
  int sum = 0, largest = 0;
  for (int i = 0; i < n; ++i) {
    q[i] = static_cast<uint16_t>(std::lround(std::clamp(w[i], 0.0f, 1.0f) * 65535.0f));
    sum += q[i];
    if (w[i] > w[largest]) largest = i;
  }
  q[largest] = static_cast<uint16_t>(std::clamp(int(q[largest]) + 65535 - sum, 0, 65535));
}
}  // namespace

glm::u16vec4 quantizeWeights(const glm::vec4& w) {
  const float in[4] = {w.x, w.y, w.z, w.w};
  uint16_t q[4];
  quantize(in, q, 4);
  return glm::u16vec4(q[0], q[1], q[2], q[3]);
}

void quantizeWeights(const glm::vec4& weights, const glm::vec4& weights1, glm::u16vec4* out,
                     glm::u16vec4* out1) {
  const float in[8] = {weights.x,  weights.y,  weights.z,  weights.w,
                       weights1.x, weights1.y, weights1.z, weights1.w};
  uint16_t q[8];
  quantize(in, q, 8);
  *out = glm::u16vec4(q[0], q[1], q[2], q[3]);
  *out1 = glm::u16vec4(q[4], q[5], q[6], q[7]);
}

glm::vec4 dequantizeWeights(const glm::u16vec4& q) { return glm::vec4(q) / 65535.0f; }

Status reduceInfluences(Span<const Influence> influences, glm::u16vec4* out_joints,
                        glm::vec4* out_weights, float* dropped_weight) {
  if (out_joints == nullptr || out_weights == nullptr)
    return {StatusCode::kInvalidArgument, "reduceInfluences: outputs must not be null"};
  double total = 0.0;
  for (size_t i = 0; i < influences.size(); ++i) {
    const Influence& in = influences[i];
    if (!std::isfinite(in.weight) || in.weight < 0.0f)
      return {StatusCode::kInvalidArgument,
              strCat("reduceInfluences: influence ", i, " weight is negative or not finite")};
    if (in.joint > 0xFFFFu)
      return {StatusCode::kOutOfRange,
              strCat("reduceInfluences: influence ", i, " joint ", in.joint, " exceeds 65535")};
    total += in.weight;
  }
  if (!(total > 0.0))
    return {StatusCode::kInvalidArgument, "reduceInfluences: weights sum to zero"};
  Influence best[kMaxInfluences] = {};
  size_t kept = 0;
  for (const Influence& in : influences) {
    // Insertion into a sorted list of at most 4: larger weight first, lower joint on ties.
    size_t pos = kept;
    while (pos > 0 && (in.weight > best[pos - 1].weight ||
                       (in.weight == best[pos - 1].weight && in.joint < best[pos - 1].joint)))
      --pos;
    if (pos >= kMaxInfluences) continue;
    for (size_t k = std::min(kept, kMaxInfluences - 1); k > pos; --k) best[k] = best[k - 1];
    best[pos] = in;
    kept = std::min(kept + 1, kMaxInfluences);
  }
  double kept_sum = 0.0;
  for (size_t k = 0; k < kept; ++k) kept_sum += best[k].weight;
  glm::u16vec4 j(0);
  glm::vec4 w(0.0f);
  for (size_t k = 0; k < kept; ++k) {
    j[int(k)] = static_cast<uint16_t>(best[k].joint);
    w[int(k)] = static_cast<float>(best[k].weight / kept_sum);
  }
  *out_joints = j;
  *out_weights = w;
  if (dropped_weight != nullptr) *dropped_weight = static_cast<float>(1.0 - kept_sum / total);
  return Status::ok();
}

std::vector<uint16_t> resolvedVertexMaterials(const SkinnedMesh& mesh) {
  if (mesh.vertex_materials.size() == mesh.vertexCount()) return mesh.vertex_materials;
  std::vector<uint16_t> out(mesh.vertexCount(), 0);
  std::vector<bool> set(mesh.vertexCount(), false);
  for (const SubMesh& sm : mesh.sub_meshes)
    for (const IndexRange& r : sm.lods)
      for (size_t i = r.first_index; i < size_t(r.first_index) + r.index_count && i < mesh.indices.size(); ++i) {
        const uint32_t v = mesh.indices[i];
        if (v >= out.size() || set[v]) continue;
        out[v] = uint16_t(std::min<uint32_t>(sm.material, UINT16_MAX));
        set[v] = true;
      }
  return out;
}

}  // namespace si
