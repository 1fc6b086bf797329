// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Root motion in core: ground motions, the root joint, M(t) from the tracks and the in-place
// poses the reference evaluator gives (si/core/root_motion.h).
#include <gtest/gtest.h>

#include "core/test_helpers.h"
#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"

namespace si {
namespace {

using test::kPi;

double yawDifference(double a, double b) { return std::fabs(std::remainder(a - b, 2.0 * kPi)); }

double matrixDifference(const glm::dmat4& a, const glm::dmat4& b) {
  double m = 0.0;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m = std::max(m, std::fabs(a[c][r] - b[c][r]));
  return m;
}

Character movingCharacter() { return test::travellingCharacter(); }

TEST(GroundMotion, AlgebraMatchesTheMatrices) {
  const GroundMotion a{{1.5, -2.0}, 0.7}, b{{-0.25, 3.0}, -2.9};
  const glm::dmat4 ab = groundMotionMatrix(a) * groundMotionMatrix(b);
  EXPECT_LT(matrixDifference(groundMotionMatrix(composeGroundMotion(a, b)), ab), 1e-12);
  EXPECT_LT(matrixDifference(groundMotionMatrix(inverseGroundMotion(a)),
                             glm::inverse(groundMotionMatrix(a))), 1e-12);
  // The matrix turns +Z towards +X for a positive yaw, as glm::angleAxis about +Y does.
  const glm::dvec4 z = groundMotionMatrix({{0, 0}, kPi / 2}) * glm::dvec4(0, 0, 1, 0);
  EXPECT_NEAR(z.x, 1.0, 1e-12);
  glm::dmat4 five(1.0);
  for (int i = 0; i < 5; ++i) five = five * groundMotionMatrix(a);
  EXPECT_LT(matrixDifference(groundMotionMatrix(repeatGroundMotion(a, 5)), five), 1e-12);
  const GroundMotion none = repeatGroundMotion(a, 0);
  EXPECT_EQ(none.translation, glm::dvec2(0.0));
  EXPECT_EQ(none.yaw, 0.0);
  // Angles wrap into (-pi, pi].
  EXPECT_NEAR(wrapAngle(1.5 * kPi), -0.5 * kPi, 1e-12);
  EXPECT_EQ(wrapAngle(-kPi), kPi);
  EXPECT_EQ(wrapAngle(kPi), kPi);
  EXPECT_NEAR(wrapAngle(7.0 * kPi + 0.25), -kPi + 0.25, 1e-12);
  // A million repeats of a pure turn: yaw adds up without wrapping.
  EXPECT_NEAR(repeatGroundMotion({{0, 0}, 1e-3}, 1000000).yaw, 1000.0, 1e-9);
}

TEST(RootMotion, TheDefaultRootJointIsTheFirstWithATranslationTrack) {
  const Character c = movingCharacter();
  const Clip& walk = c.clips[size_t(c.findClip("walk_forward"))];
  uint32_t joint = 99;
  ASSERT_TRUE(rootMotionJoint(c.skeleton, walk, &joint).isOk());
  EXPECT_EQ(c.skeleton.joint_names[joint], "root");
  Clip named = walk;
  named.root_motion.joint = "pelvis";
  ASSERT_TRUE(rootMotionJoint(c.skeleton, named, &joint).isOk());
  EXPECT_EQ(c.skeleton.joint_names[joint], "pelvis");
  named.root_motion.joint = "tail";
  const Status s = rootMotionJoint(c.skeleton, named, &joint);
  EXPECT_EQ(s.code(), StatusCode::kNotFound);
  EXPECT_NE(s.message().find("'tail'"), std::string::npos) << s.message();
  // A character carrying such a clip does not validate, and the clip does not evaluate.
  Character bad = c;
  bad.clips.push_back(named);
  EXPECT_EQ(bad.validate().code(), StatusCode::kNotFound);
  ReferencePose pose;
  EXPECT_EQ(evaluatePose(c.skeleton, named, 0.5, &pose).code(), StatusCode::kNotFound);
  GroundMotion m;
  EXPECT_EQ(evaluateRootMotion(c.skeleton, named, 0.5, &m).code(), StatusCode::kNotFound);
  EXPECT_EQ(evaluateRootMotion(c.skeleton, walk, 0.5, nullptr).code(),
            StatusCode::kInvalidArgument);
  // No tracks at all: joint 0.
  ASSERT_TRUE(rootMotionJoint(c.skeleton, test::emptyClip(c.skeleton.jointCount()), &joint).isOk());
  EXPECT_EQ(joint, 0u);
}

TEST(RootMotion, TheMovingClipsTravelAsDefined) {
  const Character c = movingCharacter();
  ASSERT_TRUE(c.validate().isOk());
  const Clip& walk = c.clips[size_t(c.findClip("walk_forward"))];
  const Clip& turn = c.clips[size_t(c.findClip("walk_turn_left"))];
  EXPECT_TRUE(walk.root_motion.extract);
  EXPECT_TRUE(turn.root_motion.extract);
  for (double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {  // Key times (25 keys per second).
    GroundMotion m;
    ASSERT_TRUE(evaluateRootMotion(c.skeleton, walk, t, &m).isOk());
    EXPECT_NEAR(m.translation.x, 0.0, 1e-6);
    EXPECT_NEAR(m.translation.y, 1.3 * t, 1e-6);
    EXPECT_NEAR(m.yaw, 0.0, 1e-6);
    ASSERT_TRUE(evaluateRootMotion(c.skeleton, turn, t, &m).isOk());
    const double a = kPi / 4 * t;  // On the circle of radius 1 / (pi / 4).
    EXPECT_NEAR(m.translation.x, (1 - std::cos(a)) / (kPi / 4), 1e-6);
    EXPECT_NEAR(m.translation.y, std::sin(a) / (kPi / 4), 1e-6);
    EXPECT_NEAR(m.yaw, a, 1e-6);
  }
}

// The evaluator's pose of an extracting clip is M(t)^-1 times the pose with the motion in it,
// at every joint: the root joint stays where it started on the ground, facing the same way.
TEST(RootMotion, ExtractedPosesAreTheFullPosesTakenBackByTheMotion) {
  const Character c = movingCharacter();
  for (const char* name : {"walk_forward", "walk_turn_left"}) {
    SCOPED_TRACE(name);
    const Clip& in_place = c.clips[size_t(c.findClip(name))];
    Clip moving = in_place;
    moving.root_motion.extract = false;
    uint32_t root = 0;
    ASSERT_TRUE(rootMotionJoint(c.skeleton, in_place, &root).isOk());
    ReferencePose start, a, b;
    ASSERT_TRUE(evaluateLocalPose(c.skeleton, in_place, 0.0, &start).isOk());
    for (double t : {0.0, 0.13, 0.5, 0.97, 1.0}) {
      GroundMotion m;
      ASSERT_TRUE(evaluateRootMotion(c.skeleton, in_place, t, &m).isOk());
      ASSERT_TRUE(evaluateLocalPose(c.skeleton, in_place, t, &a).isOk());
      ASSERT_TRUE(evaluateLocalPose(c.skeleton, moving, t, &b).isOk());
      const glm::dmat4 motion = groundMotionMatrix(m);
      for (size_t j = 0; j < c.skeleton.jointCount(); ++j) {
        EXPECT_LT(matrixDifference(motion * a.model[j], b.model[j]), 1e-12) << j;
        EXPECT_LT(matrixDifference(motion * a.skinning[j], b.skinning[j]), 1e-12) << j;
      }
      // The root's local transform was moved too: composing the locals gives the same pose.
      std::vector<glm::dmat4> model(a.model.size()), skinning(a.model.size());
      ASSERT_TRUE(composePose(c.skeleton, a.local, model, skinning).isOk());
      for (size_t j = 0; j < model.size(); ++j)
        EXPECT_LT(matrixDifference(model[j], a.model[j]), 1e-12) << j;
      EXPECT_NEAR(a.model[root][3].x, start.model[root][3].x, 1e-12);
      EXPECT_NEAR(a.model[root][3].z, start.model[root][3].z, 1e-12);
    }
  }
}

// A Z-up rig (an armature joint turned -90 degrees about X above the root joint, as exporters
// from Z-up tools write it): the motion is still over the model's ground plane and about +Y.
TEST(RootMotion, AZUpRigStillMovesOverTheGround) {
  Skeleton s = test::chainSkeleton(3);
  s.joint_names = {"armature", "hips", "spine"};
  s.rest_pose[0].rotation = test::axisAngleF(-kPi / 2, {1, 0, 0});
  s.rest_pose[1].translation = glm::vec3(0.0f);
  Clip clip = test::emptyClip(3, 2.0f);
  clip.root_motion.extract = true;
  Vec3Track& tr = clip.joint_tracks[1].translation;
  QuatTrack& rot = clip.joint_tracks[1].rotation;
  for (int k = 0; k <= 20; ++k) {
    const double t = 0.1 * k;
    tr.times_seconds.push_back(float(t));
    tr.values.push_back(glm::vec3(0.0f, float(-0.8 * t), 0.9f));  // Local -Y is model +Z.
    rot.times_seconds.push_back(float(t));
    rot.values.push_back(test::axisAngleF(0.6 * t, {0, 0, 1}));   // Local +Z is model +Y.
  }
  GroundMotion m;
  ASSERT_TRUE(evaluateRootMotion(s, clip, 1.5, &m).isOk());
  EXPECT_NEAR(m.translation.x, 0.0, 1e-6);
  EXPECT_NEAR(m.translation.y, 0.8 * 1.5, 1e-6);
  EXPECT_NEAR(m.yaw, 0.6 * 1.5, 1e-6);
  ReferencePose pose;
  ASSERT_TRUE(evaluatePose(s, clip, 1.5, &pose).isOk());
  EXPECT_NEAR(pose.model[1][3].y, 0.9, 1e-6);  // The height is kept...
  EXPECT_NEAR(pose.model[1][3].z, 0.0, 1e-6);  // ...the travel taken out.
}

// Hard cases: a turn past pi (the wrapped yaw), a root scaled to zero, a root upside down, a
// mirrored root. Each gives a finite motion and a pose that composes back exactly.
TEST(RootMotion, DegenerateRootsGiveFiniteMotions) {
  Skeleton s = test::chainSkeleton(2);
  for (int variant = 0; variant < 4; ++variant) {
    SCOPED_TRACE(variant);
    Clip clip = test::emptyClip(2, 1.0f);
    clip.root_motion.extract = true;
    JointTracks& root = clip.joint_tracks[0];
    root.translation.times_seconds = {0.0f, 1.0f};
    root.translation.values = {glm::vec3(0.0f), glm::vec3(2.0f, 0.5f, -1.0f)};
    root.rotation.times_seconds = {0.0f, 1.0f};
    root.rotation.values = {glm::quat(1, 0, 0, 0),
                            variant == 2 ? test::axisAngleF(kPi, {1, 0, 0})
                                         : test::axisAngleF(variant == 0 ? 3.0 : 0.5, {0, 1, 0})};
    if (variant == 1) {
      root.scale.times_seconds = {0.0f, 1.0f};
      root.scale.values = {glm::vec3(1.0f), glm::vec3(0.0f)};
    }
    if (variant == 3) s.rest_pose[0].scale = glm::vec3(-1.0f, 1.0f, 1.0f);
    for (double t : {0.0, 0.5, 0.99, 1.0}) {
      GroundMotion m;
      ReferencePose in_place, full;
      ASSERT_TRUE(evaluateRootMotion(s, clip, t, &m).isOk());
      EXPECT_TRUE(std::isfinite(m.translation.x) && std::isfinite(m.translation.y) &&
                  std::isfinite(m.yaw));
      EXPECT_LE(std::fabs(m.yaw), kPi);
      ASSERT_TRUE(evaluatePose(s, clip, t, &in_place).isOk());
      Clip moving = clip;
      moving.root_motion.extract = false;
      ASSERT_TRUE(evaluatePose(s, moving, t, &full).isOk());
      for (size_t j = 0; j < 2; ++j)
        EXPECT_LT(matrixDifference(groundMotionMatrix(m) * in_place.model[j], full.model[j]), 1e-12);
    }
    if (variant == 0) {  // 3 rad at t = 1: less than pi, so not wrapped.
      GroundMotion m;
      ASSERT_TRUE(evaluateRootMotion(s, clip, 1.0, &m).isOk());
      EXPECT_LT(yawDifference(m.yaw, 3.0), 1e-6);
    }
    s.rest_pose[0].scale = glm::vec3(1.0f);
  }
}

}  // namespace
}  // namespace si
