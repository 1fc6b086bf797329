// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager::jointMatrix: what the crowd says is drawn of a joint (attachments, hit tests)
// is what the instance's record draws.
#include <gtest/gtest.h>

#include "crowd/crowd_test_helpers.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/record_emulation.h"

namespace si {
namespace {

using namespace test;

TEST(CrowdManager, JointMatrixMatchesThePalette) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const BakedPalette& p = defaultPalette();
  const Character& ch = test::defaultCharacter();
  InstanceDesc d;
  d.position = glm::dvec3(5, 0, 7);
  d.clip = uint32_t(p.findClip("walk"));
  d.time_seconds = 0.3;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const uint32_t hand = uint32_t(ch.skeleton.findJoint("r_hand"));
  glm::dmat4 m;
  ASSERT_TRUE(crowd.jointMatrix(h, hand, &m).isOk());
  const glm::mat4 skin = emulateSkinningMatrix(p, d.clip, sampleFrames(p.clips[d.clip], 0.3),
                                               uint32_t(p.skeleton_to_palette[hand]));
  const glm::dvec3 bind_hand(glm::inverse(ch.skeleton.inverse_bind_matrices[hand])[3]);
  const glm::dvec3 world(m * glm::dvec4(bind_hand, 1.0));
  const glm::dvec3 expected = glm::dvec3(skin * glm::vec4(glm::vec3(bind_hand), 1.0f)) + d.position;
  EXPECT_NEAR(glm::length(world - expected), 0.0, 1e-5);
  EXPECT_EQ(crowd.jointMatrix(h, 0, &m).code(), StatusCode::kOutOfRange);  // Root not stored.
  ASSERT_TRUE(crowd.remove(h).isOk());
  EXPECT_EQ(crowd.jointMatrix(h, hand, &m).code(), StatusCode::kNotFound);
}

// An instance at a LOD past CrowdDesc::animation_lod_start is drawn at times held on the
// animation-LOD grid; jointMatrix (an attachment, a hit test) answers for the same times, so it
// matches the record, crossfade included.
TEST(CrowdManager, JointMatrixFollowsTheAnimationLodStepping) {
  CrowdDesc cd = defaultCrowdDesc();
  cd.animation_lod_start = 1;
  cd.animation_lod_rate_hz = 10.0f;
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  const BakedPalette& p = defaultPalette();
  const Character& ch = test::defaultCharacter();
  InstanceDesc d;
  d.position = glm::dvec3(0, 0, -70);  // Past the first LOD line, in view.
  d.clip = uint32_t(p.findClip("walk"));
  d.time_seconds = 0.37;  // Off the 0.1 s grid.
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.crossfade(h, uint32_t(p.findClip("run")), 0.5).isOk());
  const Camera camera = testCamera({0, 1.6, 0}, {0, 1, -70});
  ASSERT_TRUE(crowd.update(0.12, camera).isOk());
  uint32_t lod = 0;
  ASSERT_TRUE(crowd.lodOf(h, &lod).isOk());
  ASSERT_GE(lod, 1u);
  ASSERT_EQ(crowd.records().size(), 1u);
  const uint32_t hand = uint32_t(ch.skeleton.findJoint("r_hand"));
  glm::dmat4 m;
  ASSERT_TRUE(crowd.jointMatrix(h, hand, &m).isOk());
  const glm::mat4 drawn =
      emulateRecordMatrix(p, crowd.records()[0], uint32_t(p.skeleton_to_palette[hand]));
  const glm::dvec4 bind_hand(glm::dvec3(glm::inverse(ch.skeleton.inverse_bind_matrices[hand])[3]),
                             1.0);
  const glm::dvec3 expected = glm::dvec3(glm::dmat4(drawn) * bind_hand) + d.position;
  EXPECT_LT(glm::length(glm::dvec3(m * bind_hand) - expected), 1e-5);
}

}  // namespace
}  // namespace si
