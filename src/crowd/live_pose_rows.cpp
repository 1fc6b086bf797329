// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd/live_pose_rows.h"

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_access.hpp>

#include "core/palette_texel.h"
#include "crowd/live_pose_lanes.h"

namespace si::detail {

size_t firstBadJointReference(Span<const glm::mat4> skinning, float range) {
  for (size_t k = 0; k < skinning.size(); ++k) {
    const glm::mat4& m = skinning[k];
    bool bad = m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r) bad |= !(std::fabs(m[c][r]) <= range);
    if (bad) return k;
  }
  return skinning.size();
}

void storeJointRowsReference(PaletteFormat format, Span<const glm::mat4> skinning,
                             uint32_t joint_stride_texels, uint8_t* frame) {
  for (size_t j = 0; j < skinning.size(); ++j)
    for (uint32_t row = 0; row < 3; ++row)
      storeFormatTexel(format, frame, j * joint_stride_texels + row,
                       glm::row(skinning[j], int(row)));
}

std::vector<JointBox> jointBoxes(Span<const Aabb> joint_bounds) {
  std::vector<JointBox> out(joint_bounds.size());
  for (size_t j = 0; j < joint_bounds.size(); ++j) {
    const Aabb& b = joint_bounds[j];
    if (b.empty()) continue;
    out[j].center = glm::vec4(0.5f * (b.min + b.max), 0.0f);
    out[j].half = glm::vec4(0.5f * (b.max - b.min), 0.0f);
  }
  return out;
}

Aabb poseBoxReference(Span<const glm::mat4> skinning, Span<const JointBox> joints) {
  Aabb box;
  bool nan = false;
  for (size_t j = 0; j < skinning.size(); ++j) {
    const JointBox& b = joints[j];
    if (b.half.x < 0.0f) continue;
    const glm::mat4& m = skinning[j];
    const glm::vec3 center = glm::vec3(m[0]) * b.center.x + glm::vec3(m[1]) * b.center.y +
                             glm::vec3(m[2]) * b.center.z + glm::vec3(m[3]);
    const glm::vec3 half = glm::abs(glm::vec3(m[0])) * b.half.x +
                           glm::abs(glm::vec3(m[1])) * b.half.y +
                           glm::abs(glm::vec3(m[2])) * b.half.z;
    nan |= std::isnan(center.x) || std::isnan(center.y) || std::isnan(center.z);
    box.extend(center - half);
    box.extend(center + half);
  }
  if (nan) box.min = box.max = glm::vec3(std::numeric_limits<float>::quiet_NaN());
  return box;
}

namespace {

size_t storePoseReference(PaletteFormat format, Span<const glm::mat4> skinning,
                          uint32_t joint_stride_texels, Span<const JointBox> joints, float range,
                          uint8_t* frame, Aabb* box) {
  const size_t bad = firstBadJointReference(skinning, range);
  if (bad < skinning.size()) return bad;
  storeJointRowsReference(format, skinning, joint_stride_texels, frame);
  *box = joints.empty() ? Aabb() : poseBoxReference(skinning, joints);
  return skinning.size();
}

PoseRowsIsa bestIsa() {
  static const PoseRowsIsa best = runs(PoseRowsIsa::kF16c)   ? PoseRowsIsa::kF16c
                                  : runs(PoseRowsIsa::kSse2) ? PoseRowsIsa::kSse2
                                                             : PoseRowsIsa::kReference;
  return best;
}

}  // namespace

bool runs(PoseRowsIsa isa) {
  switch (isa) {
    case PoseRowsIsa::kSse2:
#if SI_LIVE_ROWS_SSE2
      return true;
#else
      return false;
#endif
    case PoseRowsIsa::kF16c: {
#if SI_LIVE_ROWS_F16C
      static const bool f16c = cpuRunsF16c();
      return f16c;
#else
      return false;
#endif
    }
    case PoseRowsIsa::kReference:
    case PoseRowsIsa::kBest:
      return true;
  }
  return false;
}

size_t storePose(PaletteFormat format, Span<const glm::mat4> skinning, uint32_t joint_stride_texels,
                 Span<const JointBox> joints, float range, uint8_t* frame, Aabb* box,
                 PoseRowsIsa isa) {
  if (isa == PoseRowsIsa::kBest) isa = bestIsa();
  switch (isa) {
#if SI_LIVE_ROWS_F16C
    case PoseRowsIsa::kF16c:
      return storePoseF16c(format, skinning, joint_stride_texels, joints, range, frame, box);
#endif
#if SI_LIVE_ROWS_SSE2
    case PoseRowsIsa::kSse2:
      return storePoseSse2(format, skinning, joint_stride_texels, joints, range, frame, box);
#endif
    default:
      return storePoseReference(format, skinning, joint_stride_texels, joints, range, frame, box);
  }
}

}  // namespace si::detail
