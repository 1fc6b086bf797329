// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The inner loops of the baker's measurement: the shader's skinning against the reference's
// for many vertices at one time, and the exact 99th percentile of a long stream of errors.
#include <cstdint>
#include <vector>

#include "si/core/skinned_mesh.h"
#include "si/core/span.h"

namespace si::detail {

/// Vertices grouped by their influences (joints, the vertex format's weights and the
/// source's), gathered once: at each time a group's blended 3x4 matrix is formed once and each
/// of its vertices costs 12 multiply-adds, in float over contiguous positions (a rigid part,
/// or a ring of equally weighted vertices, is one group).
class InfluenceGroups {
 public:
  /// `vertices` index `mesh` (the source weights) and `gpu_mesh` (the same vertices with the
  /// weights the vertex format stores); joints must be below the matrices' count later.
  InfluenceGroups(const SkinnedMesh& mesh, const SkinnedMesh& gpu_mesh,
                  const std::vector<uint32_t>& vertices);

  /// Vertices held, and the vertex of each slot (slots run group by group).
  size_t size() const { return vertex_.size(); }
  uint32_t vertex(size_t slot) const { return vertex_[slot]; }
  size_t groupCount() const { return group_start_.size() - 1; }

  /// Per slot, |shader - reference|: the shader blends `emulated` with the stored weights (zero
  /// weights skipped), the reference blends `reference` with the source's. The two are
  /// subtracted per joint before the vertex is transformed, so float keeps the small
  /// difference's precision.
  void errors(Span<const glm::mat4> emulated, Span<const glm::dmat4> reference,
              std::vector<float>* out) const;
  /// Per slot, the shader's position under `emulated`.
  void positions(Span<const glm::mat4> emulated, std::vector<glm::vec3>* out) const;

 private:
  struct Influences {
    uint16_t joint[kMaxVertexInfluences];
    float wq[kMaxVertexInfluences];  // The vertex format's weight (0 where both are 0).
    float w[kMaxVertexInfluences];   // The source's.
  };
  std::vector<Influences> groups_;
  std::vector<uint32_t> group_start_;  // groupCount() + 1 slot offsets.
  std::vector<uint32_t> vertex_;
  std::vector<float> x_, y_, z_;       // Positions per slot.
};

/// The k-th largest of a stream, exactly, in memory for 2k values: candidates above the running
/// threshold are kept and trimmed to the k largest whenever 2k have gathered.
class LargestK {
 public:
  explicit LargestK(uint64_t k);
  void add(float e) {
    if (full_ && !(e > threshold_)) return;
    values_.push_back(e);
    if (values_.size() >= 2 * k_) trim();
  }
  /// The k-th largest value added (the smallest when fewer were added; 0 when none).
  float kth();

 private:
  void trim();
  uint64_t k_;
  bool full_ = false;  // k values at least threshold_ are held.
  float threshold_ = 0.0f;
  std::vector<float> values_;
};

}  // namespace si::detail
