// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Instance positions and rotations stored in blocks of 8 instances, one array per component
// within a block (x[8], y[8], z[8], ...): the frame builder loads 8 lanes of a component with
// vector loads instead of gathering them from structures, and the instances still lie in one
// memory stream, in order. (Measured on the 2-core VM, 1M instances: one array per component,
// 7 streams, and blocks of 64, whose component rows a one-instance reader jumps between, each
// made the frame 10-20 % slower than structures; blocks of 8 did not.)

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace si::detail {

/// Instances per block: the frame builder's lanes (cull::kLanes, kRecordLanes).
inline constexpr uint32_t kColumnBlock = 8;

/// Columns of `Block` (arrays of kColumnBlock per component) for `size()` instances.
template <typename Block>
struct BlockColumns {
  std::vector<Block> blocks;
  uint32_t count = 0;
  size_t size() const { return count; }
  const Block& blockOf(uint32_t i) const { return blocks[i / kColumnBlock]; }
  Block& blockOf(uint32_t i) { return blocks[i / kColumnBlock]; }
  /// Appends a zeroed instance; its index.
  uint32_t grow() {
    if (count % kColumnBlock == 0) blocks.emplace_back();
    return count++;
  }
  /// Drops the last instance.
  void shrink() {
    if (--count % kColumnBlock == 0) blocks.pop_back();
  }
};

struct DVec3Block {
  double x[kColumnBlock], y[kColumnBlock], z[kColumnBlock];
};

/// Positions in double.
struct DVec3Columns : BlockColumns<DVec3Block> {
  glm::dvec3 get(uint32_t i) const {
    const DVec3Block& b = blockOf(i);
    const uint32_t k = i % kColumnBlock;
    return {b.x[k], b.y[k], b.z[k]};
  }
  void set(uint32_t i, const glm::dvec3& v) {
    DVec3Block& b = blockOf(i);
    const uint32_t k = i % kColumnBlock;
    b.x[k] = v.x, b.y[k] = v.y, b.z[k] = v.z;
  }
  void push(const glm::dvec3& v) { set(grow(), v); }
  /// Moves the last element into `i` and drops the last.
  void moveLast(uint32_t i) {
    set(i, get(count - 1));
    shrink();
  }
};

struct QuatBlock {
  float x[kColumnBlock], y[kColumnBlock], z[kColumnBlock], w[kColumnBlock];
};

/// Rotations (glm::quat's components).
struct QuatColumns : BlockColumns<QuatBlock> {
  glm::quat get(uint32_t i) const {
    const QuatBlock& b = blockOf(i);
    const uint32_t k = i % kColumnBlock;
    return glm::quat(b.w[k], b.x[k], b.y[k], b.z[k]);
  }
  void set(uint32_t i, const glm::quat& q) {
    QuatBlock& b = blockOf(i);
    const uint32_t k = i % kColumnBlock;
    b.x[k] = q.x, b.y[k] = q.y, b.z[k] = q.z, b.w[k] = q.w;
  }
  void push(const glm::quat& q) { set(grow(), q); }
  void moveLast(uint32_t i) {
    set(i, get(count - 1));
    shrink();
  }
};

}  // namespace si::detail
