// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "bake/error_kernel.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>

namespace si::detail {

namespace {

// A 3x4 matrix as rows, accumulated in float.
struct Rows {
  float m[12];
};

bool lessInfluences(const uint16_t* ja, const float* wa, const float* qa, const uint16_t* jb,
                    const float* wb, const float* qb) {
  for (size_t k = 0; k < kMaxVertexInfluences; ++k) {
    if (ja[k] != jb[k]) return ja[k] < jb[k];
    if (wa[k] != wb[k]) return wa[k] < wb[k];
    if (qa[k] != qb[k]) return qa[k] < qb[k];
  }
  return false;
}

}  // namespace

InfluenceGroups::InfluenceGroups(const SkinnedMesh& mesh, const SkinnedMesh& gpu_mesh,
                                 const std::vector<uint32_t>& vertices) {
  struct Key {
    Influences in;
    bool operator<(const Key& o) const {
      return lessInfluences(in.joint, in.w, in.wq, o.in.joint, o.in.w, o.in.wq);
    }
  };
  std::map<Key, std::vector<uint32_t>> by_influences;
  for (uint32_t v : vertices) {
    Key key{};
    for (size_t k = 0; k < mesh.influenceCount(); ++k) {
      const float w = mesh.influence(v, k).weight, wq = gpu_mesh.influence(v, k).weight;
      const bool used = w != 0.0f || wq != 0.0f;
      key.in.joint[k] = used ? uint16_t(mesh.influence(v, k).joint) : 0;
      key.in.w[k] = used ? w : 0.0f;
      key.in.wq[k] = used ? wq : 0.0f;
    }
    by_influences[key].push_back(v);
  }
  group_start_.push_back(0);
  for (const auto& [key, list] : by_influences) {
    groups_.push_back(key.in);
    for (uint32_t v : list) {
      vertex_.push_back(v);
      x_.push_back(mesh.positions[v].x);
      y_.push_back(mesh.positions[v].y);
      z_.push_back(mesh.positions[v].z);
    }
    group_start_.push_back(uint32_t(vertex_.size()));
  }
}

void InfluenceGroups::errors(Span<const glm::mat4> emulated, Span<const glm::dmat4> reference,
                             std::vector<float>* out) const {
  out->resize(vertex_.size());
  float* e = out->data();
  for (size_t g = 0; g < groups_.size(); ++g) {
    const Influences& in = groups_[g];
    // sum over influences of wq E - w R, in double before it is rounded to float: the small
    // difference keeps its precision.
    double a[12] = {};
    for (size_t k = 0; k < kMaxVertexInfluences; ++k) {
      if (in.wq[k] == 0.0f && in.w[k] == 0.0f) continue;
      const glm::mat4& em = emulated[in.joint[k]];
      const glm::dmat4& rm = reference[in.joint[k]];
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
          a[row * 4 + col] += double(in.wq[k]) * double(em[col][row]) - double(in.w[k]) * rm[col][row];
    }
    float f[12];
    for (int i = 0; i < 12; ++i) f[i] = float(a[i]);
    for (uint32_t s = group_start_[g]; s < group_start_[g + 1]; ++s) {
      const float x = x_[s], y = y_[s], z = z_[s];
      const float ex = f[0] * x + f[1] * y + f[2] * z + f[3];
      const float ey = f[4] * x + f[5] * y + f[6] * z + f[7];
      const float ez = f[8] * x + f[9] * y + f[10] * z + f[11];
      e[s] = std::sqrt(ex * ex + ey * ey + ez * ez);
    }
  }
}

void InfluenceGroups::positions(Span<const glm::mat4> emulated, std::vector<glm::vec3>* out) const {
  out->resize(vertex_.size());
  for (size_t g = 0; g < groups_.size(); ++g) {
    const Influences& in = groups_[g];
    // As the shader: blend the influences' matrices (zero weights skipped), then transform.
    glm::mat4 m(0.0f);
    for (size_t k = 0; k < kMaxVertexInfluences; ++k)
      if (in.wq[k] != 0.0f) m += emulated[in.joint[k]] * in.wq[k];
    for (uint32_t s = group_start_[g]; s < group_start_[g + 1]; ++s)
      (*out)[s] = glm::vec3(m * glm::vec4(x_[s], y_[s], z_[s], 1.0f));
  }
}

LargestK::LargestK(uint64_t k) : k_(std::max<uint64_t>(k, 1)) {}

float LargestK::kth() {
  trim();
  return values_.empty() ? 0.0f : *std::min_element(values_.begin(), values_.end());
}

void LargestK::trim() {
  if (values_.size() > k_) {
    std::nth_element(values_.begin(), values_.begin() + std::ptrdiff_t(k_ - 1), values_.end(),
                     std::greater<float>());
    values_.resize(k_);
  }
  if (values_.size() >= k_) {
    threshold_ = *std::min_element(values_.begin(), values_.end());
    full_ = true;
  }
}

}  // namespace si::detail
