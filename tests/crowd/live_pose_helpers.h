// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the live-pose tests share: a pose unlike any clip's, an instance's record in the crowd's
// own view, and the default crowd with room for live poses.

#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "crowd/crowd_test_helpers.h"
#include "si/core/baked_palette.h"
#include "si/core/skeleton.h"
#include "si/crowd/crowd_manager.h"

namespace si::test {

// A pose unlike any clip's: each stored joint's bind-pose skinning matrix turned about its
// joint and moved, by amounts that differ per joint.
inline std::vector<glm::mat4> enginePose(const Skeleton& sk, const BakedPalette& p) {
  std::vector<glm::mat4> out;
  for (uint32_t slot = 0; slot < p.palette_joints.size(); ++slot) {
    const glm::mat4 bind = glm::inverse(sk.inverse_bind_matrices[p.palette_joints[slot]]);
    const glm::vec3 at(bind[3]);
    glm::mat4 m = glm::translate(glm::mat4(1.0f), at + glm::vec3(0.01f * float(slot), 0.2f, 0.0f)) *
                  glm::mat4_cast(glm::angleAxis(0.1f * float(slot + 1), glm::vec3(0, 1, 0))) *
                  glm::translate(glm::mat4(1.0f), -at);
    out.push_back(m);
  }
  return out;
}

// The record of `h` in the crowd's own view.
inline const InstanceRecord* recordOf(const CrowdManager& crowd, InstanceHandle h) {
  const CrowdView& v = crowd.view();
  for (size_t k = 0; k < v.records().size(); ++k)
    if (v.visibleHandles()[k] == h) return &v.records()[k];
  return nullptr;
}

inline CrowdDesc liveDesc(uint32_t capacity) {
  CrowdDesc d = defaultCrowdDesc();
  d.live_pose_capacity = capacity;
  return d;
}

// A crowd of `character` baked into `palette` (one LOD), with room for `capacity` live poses.
inline CrowdDesc liveDesc(const BakedPalette& palette, const Character& character,
                          uint32_t capacity) {
  CrowdDesc d;
  d.palette = &palette;
  d.sub_mesh_count = uint32_t(character.mesh.sub_meshes.size());
  d.live_pose_capacity = capacity;
  return d;
}

}  // namespace si::test
