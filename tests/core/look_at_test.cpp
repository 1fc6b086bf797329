// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// si::applyLookAt: a chain turns so that its last joint looks at the target, each joint within
// its share and limit, and nothing else moves; si::decomposePose gives composePose's inverse.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "si/core/look_at.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {

constexpr double kPi = 3.141592653589793;
enum : uint32_t { kRoot, kSpine, kNeck, kHead, kHeadEnd, kArm, kJoints };

// A small upright chain (root, spine, neck, head, head end; an arm off the spine) whose bind
// pose is its rest pose; the root turned by `root_turn` and scaled by `root_scale`.
Skeleton chainSkeleton(const glm::dquat& root_turn = glm::dquat(1, 0, 0, 0),
                       const glm::dvec3& root_scale = glm::dvec3(1.0)) {
  Skeleton s;
  s.joint_names = {"root", "spine", "neck", "head", "head_end", "arm"};
  s.parents = {Skeleton::kNoParent, kRoot, kSpine, kNeck, kHead, kSpine};
  s.rest_pose.resize(kJoints);
  s.rest_pose[kRoot].rotation = glm::quat(root_turn);
  s.rest_pose[kRoot].scale = glm::vec3(root_scale);
  s.rest_pose[kSpine].translation = {0.0f, 1.0f, 0.0f};
  s.rest_pose[kNeck].translation = {0.0f, 0.5f, 0.0f};
  s.rest_pose[kNeck].rotation = glm::angleAxis(0.2f, glm::vec3(1, 0, 0));
  s.rest_pose[kHead].translation = {0.0f, 0.2f, 0.0f};
  s.rest_pose[kHeadEnd].translation = {0.0f, 0.1f, 0.1f};
  s.rest_pose[kArm].translation = {0.3f, 0.4f, 0.0f};
  s.inverse_bind_matrices.resize(kJoints);
  std::vector<TransformD> local(kJoints);
  for (uint32_t j = 0; j < kJoints; ++j) local[j] = TransformD::fromFloat(s.rest_pose[j]);
  std::vector<glm::dmat4> model(kJoints), skinning(kJoints);
  EXPECT_TRUE(composePose(s, local, model, skinning).isOk());
  for (uint32_t j = 0; j < kJoints; ++j) s.inverse_bind_matrices[j] = glm::inverse(model[j]);
  return s;
}

std::vector<TransformD> restPose(const Skeleton& s) {
  std::vector<TransformD> local(s.jointCount());
  for (size_t j = 0; j < local.size(); ++j) local[j] = TransformD::fromFloat(s.rest_pose[j]);
  return local;
}

std::vector<glm::dmat4> modelOf(const Skeleton& s, const std::vector<TransformD>& local) {
  std::vector<glm::dmat4> model(local.size()), skinning(local.size());
  EXPECT_TRUE(composePose(s, local, model, skinning).isOk());
  return model;
}

// Where joint j looks in `model` (the bind pose's `forward` carried by the joint), unit length.
glm::dvec3 forwardOf(const Skeleton& s, const std::vector<glm::dmat4>& model, uint32_t j,
                     const glm::dvec3& forward = {0, 0, 1}) {
  return glm::normalize(glm::dmat3(model[j]) *
                        (glm::dmat3(glm::dmat4(s.inverse_bind_matrices[j])) * forward));
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0));
}

bool sameTransform(const TransformD& a, const TransformD& b) {
  return a.translation == b.translation && a.rotation == b.rotation && a.scale == b.scale;
}

TEST(LookAt, TheLastJointLooksAtTheTargetAndTheOthersTakeTheirShare) {
  // Without the root's turn and scale, then with them (turned, scaled 2, mirrored in x).
  const Skeleton skeletons[] = {
      chainSkeleton(),
      chainSkeleton(glm::angleAxis(0.7, glm::normalize(glm::dvec3(1, 2, 3))), {2.0, 2.0, 2.0}),
      chainSkeleton(glm::dquat(1, 0, 0, 0), {-1.0, 1.0, 1.0})};
  for (const Skeleton& s : skeletons) {
    SCOPED_TRACE(s.rest_pose[kRoot].scale.x);
    const std::vector<TransformD> before = restPose(s);
    const std::vector<glm::dmat4> m0 = modelOf(s, before);
    const glm::dvec3 target = glm::dvec3(m0[kHead][3]) + glm::dvec3(2.0, 0.8, 1.5);
    LookAt look;
    look.chain = {{kNeck, 0.5, kPi}, {kHead, 1.0, kPi}};
    std::vector<TransformD> pose = before;
    ASSERT_TRUE(applyLookAt(s, look, target, pose).isOk());
    const std::vector<glm::dmat4> m1 = modelOf(s, pose);
    // The neck turned half its angle to the target; the head looks at it.
    const double neck_angle =
        angleBetween(forwardOf(s, m0, kNeck), target - glm::dvec3(m0[kNeck][3]));
    EXPECT_NEAR(angleBetween(forwardOf(s, m0, kNeck), forwardOf(s, m1, kNeck)), 0.5 * neck_angle,
                1e-9);
    EXPECT_LT(angleBetween(forwardOf(s, m1, kHead), target - glm::dvec3(m1[kHead][3])), 1e-9);
    // Only the chain's rotations changed.
    for (uint32_t j : {kRoot, kSpine, kHeadEnd, kArm})
      EXPECT_TRUE(sameTransform(pose[j], before[j])) << j;
    for (uint32_t j : {kNeck, kHead}) {
      EXPECT_EQ(pose[j].translation, before[j].translation);
      EXPECT_EQ(pose[j].scale, before[j].scale);
    }
  }
}

TEST(LookAt, ALimitCapsTheTurnAndTheWeightScalesIt) {
  const Skeleton s = chainSkeleton();
  const std::vector<TransformD> before = restPose(s);
  const std::vector<glm::dmat4> m0 = modelOf(s, before);
  const glm::dvec3 head(m0[kHead][3]);
  const glm::dvec3 f0 = forwardOf(s, m0, kHead);
  // 90 degrees to the side of where the head looks.
  const glm::dvec3 side = glm::normalize(glm::cross(f0, glm::dvec3(0, 1, 0)));
  const glm::dvec3 target = head + 3.0 * side;
  const double full = angleBetween(f0, target - head);
  ASSERT_NEAR(full, 0.5 * kPi, 1e-6);
  const struct {
    double limit, weight, turned;
  } cases[] = {{glm::radians(30.0), 1.0, glm::radians(30.0)},
               {kPi, 0.25, 0.25 * full},
               {glm::radians(30.0), 0.5, glm::radians(15.0)},
               {0.0, 1.0, 0.0}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.limit);
    SCOPED_TRACE(c.weight);
    LookAt look;
    look.chain = {{kHead, 1.0, c.limit}};
    look.weight = c.weight;
    std::vector<TransformD> pose = before;
    ASSERT_TRUE(applyLookAt(s, look, target, pose).isOk());
    const glm::dvec3 f1 = forwardOf(s, modelOf(s, pose), kHead);
    EXPECT_NEAR(angleBetween(f0, f1), c.turned, 1e-9);
    EXPECT_NEAR(angleBetween(f1, target - head), full - c.turned, 1e-9);  // Towards it.
  }
  // Weight 0 leaves the pose as it is, bit for bit.
  LookAt off;
  off.chain = {{kHead, 1.0, kPi}};
  off.weight = 0.0;
  std::vector<TransformD> pose = before;
  ASSERT_TRUE(applyLookAt(s, off, target, pose).isOk());
  for (uint32_t j = 0; j < kJoints; ++j) EXPECT_TRUE(sameTransform(pose[j], before[j])) << j;
}

TEST(LookAt, ATargetBehindOrAtTheJointIsHandled) {
  const Skeleton s = chainSkeleton();
  const std::vector<TransformD> before = restPose(s);
  const std::vector<glm::dmat4> m0 = modelOf(s, before);
  const glm::dvec3 head(m0[kHead][3]);
  LookAt look;
  look.chain = {{kHead, 1.0, kPi}};
  std::vector<TransformD> pose = before;
  const glm::dvec3 behind = head - 2.0 * forwardOf(s, m0, kHead);
  ASSERT_TRUE(applyLookAt(s, look, behind, pose).isOk());
  const std::vector<glm::dmat4> m1 = modelOf(s, pose);
  EXPECT_LT(angleBetween(forwardOf(s, m1, kHead), behind - glm::dvec3(m1[kHead][3])), 1e-9);
  pose = before;
  ASSERT_TRUE(applyLookAt(s, look, head, pose).isOk());  // At the joint: no direction, no turn.
  EXPECT_TRUE(sameTransform(pose[kHead], before[kHead]));
}

TEST(LookAt, BadInputIsRefusedByNameAndThePoseKept) {
  const Skeleton s = chainSkeleton();
  const std::vector<TransformD> before = restPose(s);
  const glm::dvec3 target(1, 2, 3);
  const auto refused = [&](const LookAt& look, StatusCode code, const char* words,
                           glm::dvec3 at = glm::dvec3(1, 2, 3)) {
    std::vector<TransformD> pose = before;
    const Status st = applyLookAt(s, look, at, pose);
    EXPECT_EQ(st.code(), code) << st.message();
    EXPECT_NE(st.message().find(words), std::string::npos) << st.message();
    for (uint32_t j = 0; j < kJoints; ++j) EXPECT_TRUE(sameTransform(pose[j], before[j])) << j;
  };
  LookAt good;
  good.chain = {{kNeck, 0.5, 1.0}, {kHead, 1.0, 1.0}};
  LookAt bad = good;
  bad.chain.clear();
  refused(bad, StatusCode::kInvalidArgument, "chain is empty");
  bad = good, bad.chain[1].joint = kJoints;
  refused(bad, StatusCode::kOutOfRange, "chain[1] joint 6 is past");
  bad = good, bad.chain[1].joint = kArm;  // Not under the neck.
  refused(bad, StatusCode::kNotSorted, "does not descend from chain[0]");
  bad = good, std::swap(bad.chain[0], bad.chain[1]);  // Leaf first.
  refused(bad, StatusCode::kNotSorted, "does not descend");
  bad = good, bad.chain[0].share = 0.0;
  refused(bad, StatusCode::kInvalidArgument, "chain[0] share");
  bad = good, bad.chain[1].share = std::nan("");
  refused(bad, StatusCode::kInvalidArgument, "chain[1] share");
  bad = good, bad.chain[0].max_angle_radians = -0.1;
  refused(bad, StatusCode::kInvalidArgument, "max_angle_radians");
  bad = good, bad.chain[0].max_angle_radians = 4.0;
  refused(bad, StatusCode::kInvalidArgument, "max_angle_radians");
  bad = good, bad.weight = 1.5;
  refused(bad, StatusCode::kInvalidArgument, "weight");
  bad = good, bad.forward = glm::dvec3(0.0);
  refused(bad, StatusCode::kInvalidArgument, "forward");
  refused(good, StatusCode::kNotFinite, "target", glm::dvec3(0, std::nan(""), 0));
  std::vector<TransformD> short_pose(kJoints - 1);
  EXPECT_EQ(applyLookAt(s, good, target, short_pose).code(), StatusCode::kCountMismatch);
  // A head of zero scale: its frame is singular, found after the neck has turned.
  std::vector<TransformD> pose = before;
  pose[kHead].scale = glm::dvec3(0.0);
  const std::vector<TransformD> squashed = pose;
  const Status st = applyLookAt(s, good, target, pose);
  EXPECT_EQ(st.code(), StatusCode::kNotFinite) << st.message();
  for (uint32_t j = 0; j < kJoints; ++j) EXPECT_TRUE(sameTransform(pose[j], squashed[j])) << j;
}

TEST(DecomposePose, GivesBackTheComposedPose) {
  Skeleton s = chainSkeleton(glm::angleAxis(0.4, glm::dvec3(0, 1, 0)), {1.5, 1.5, 1.5});
  std::vector<TransformD> local = restPose(s);
  local[kSpine].rotation = glm::angleAxis(0.3, glm::normalize(glm::dvec3(1, 0, 1)));
  local[kSpine].scale = {1.0, 2.0, 0.5};  // Non-uniform: its children's model matrices shear.
  local[kNeck].scale = {-1.0, 1.0, 1.0};  // Mirrored.
  local[kArm].rotation = glm::angleAxis(-1.2, glm::dvec3(0, 0, 1));
  local[kArm].scale = {0.8, 1.1, 1.3};
  const std::vector<glm::dmat4> model = modelOf(s, local);
  std::vector<TransformD> back(kJoints);
  ASSERT_TRUE(decomposePose(s, model, back).isOk());
  for (uint32_t j = 0; j < kJoints; ++j) {
    SCOPED_TRACE(j);
    EXPECT_LT(glm::length(back[j].translation - local[j].translation), 1e-12);
    EXPECT_LT(glm::length(back[j].scale - local[j].scale), 1e-12);
    // The same rotation (q and -q alike).
    EXPECT_NEAR(std::abs(glm::dot(back[j].rotation, glm::normalize(local[j].rotation))), 1.0,
                1e-12);
  }
  const std::vector<glm::dmat4> again = modelOf(s, back);
  for (uint32_t j = 0; j < kJoints; ++j)
    for (int c = 0; c < 4; ++c) EXPECT_LT(glm::length(again[j][c] - model[j][c]), 1e-12) << j;
}

TEST(DecomposePose, ABlendOfTwoTurnsKeepsTheTurnBetweenThem) {
  // Rows of two poses blended half and half (a crossfade): its turn is halfway, its scale along
  // the turned axes cos(half the angle), the shear dropped.
  Skeleton s = chainSkeleton();
  std::vector<glm::dmat4> model = modelOf(s, restPose(s));
  const double angle = glm::radians(60.0);
  const glm::dmat4 a = glm::dmat4(1.0),
                   b = glm::mat4_cast(glm::angleAxis(angle, glm::dvec3(0, 0, 1)));
  model[kRoot] = 0.5 * a + 0.5 * b;
  std::vector<TransformD> back(kJoints);
  ASSERT_TRUE(decomposePose(s, model, back).isOk());
  const glm::dquat half = glm::angleAxis(0.5 * angle, glm::dvec3(0, 0, 1));
  EXPECT_NEAR(std::abs(glm::dot(back[kRoot].rotation, half)), 1.0, 1e-12);
  EXPECT_NEAR(back[kRoot].scale.x, std::cos(0.5 * angle), 1e-12);
  EXPECT_NEAR(back[kRoot].scale.z, 1.0, 1e-12);
  // Refusals: sizes, and a singular parent.
  std::vector<TransformD> short_out(kJoints - 1);
  EXPECT_EQ(decomposePose(s, model, short_out).code(), StatusCode::kCountMismatch);
  model[kSpine] = glm::dmat4(0.0);
  const Status st = decomposePose(s, model, back);
  EXPECT_EQ(st.code(), StatusCode::kNotFinite);
  EXPECT_NE(st.message().find("joint 1"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace si
