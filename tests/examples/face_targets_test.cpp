// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The demo's generated face targets (examples/common/face_targets.h): bounded, the head moves
// no farther with 200 targets than with 6, where targets at full size each (the benchmarks')
// add up past that.
#include <gtest/gtest.h>

#include <algorithm>
#include <unordered_map>

#include "common/face_targets.h"
#include "si/core/default_character.h"

namespace si::examples {
namespace {

// The farthest any vertex moves with every target at weight 1, as a fraction of the height.
float farthestMove(size_t targets, bool bounded) {
  Character c;
  if (!makeDefaultCharacter({}, &c).isOk()) return -1.0f;
  addFaceTargets(&c, targets, findHeadJoint(c.skeleton), bounded);
  std::unordered_map<uint32_t, glm::vec3> moved;
  for (const MorphTarget& t : c.mesh.morph_targets)
    for (size_t k = 0; k < t.vertices.size(); ++k) moved[t.vertices[k]] += t.position_deltas[k];
  float farthest = 0.0f;
  for (const auto& [vertex, delta] : moved) farthest = std::max(farthest, glm::length(delta));
  return farthest / c.height();
}

TEST(FaceTargets, BoundedTargetsKeepTheHeadsSizeWhateverTheirNumber) {
  for (size_t targets : {6u, 50u, 200u}) {
    const float bounded = farthestMove(targets, true);
    EXPECT_GT(bounded, 0.005f) << targets;  // Still a visible change.
    EXPECT_LT(bounded, 0.06f) << targets;
  }
  EXPECT_EQ(farthestMove(6, true), farthestMove(6, false));  // Few targets: as they were.
  EXPECT_GT(farthestMove(50, false), 0.1f);                  // Unbounded, 50 add up.
}

}  // namespace
}  // namespace si::examples
