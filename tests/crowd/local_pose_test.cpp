// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager::localPose: an instance's pose as drawn, as local transforms an engine's IK or
// look-at starts from; composed again it gives back what jointMatrix says is drawn.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "crowd/crowd_test_helpers.h"
#include "si/core/look_at.h"
#include "si/core/reference_evaluator.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using test::defaultCharacter;
using test::defaultPalette;

// The largest distance, over every stored joint, between where `skinning` (model space) and
// the crowd's jointMatrix (world, taken back to model space) put the joint's bind-pose
// position and points 0.1 units off it along each axis.
double largestGap(const CrowdManager& crowd, InstanceHandle h, const glm::dmat4& world,
                  const std::vector<glm::dmat4>& skinning) {
  const Skeleton& sk = defaultCharacter().skeleton;
  const BakedPalette& p = defaultPalette();
  double gap = 0.0;
  for (uint32_t j = 0; j < sk.jointCount(); ++j) {
    if (p.skeleton_to_palette[j] < 0) continue;
    glm::dmat4 drawn;
    EXPECT_TRUE(crowd.jointMatrix(h, j, &drawn).isOk());
    drawn = glm::inverse(world) * drawn;
    const glm::dvec3 at(glm::inverse(glm::dmat4(sk.inverse_bind_matrices[j]))[3]);
    for (const glm::dvec3 off :
         {glm::dvec3(0), glm::dvec3(0.1, 0, 0), glm::dvec3(0, 0.1, 0), glm::dvec3(0, 0, 0.1)}) {
      const glm::dvec4 point(at + off, 1.0);
      gap = std::max(gap, glm::length(glm::dvec3(skinning[j] * point - drawn * point)));
    }
  }
  return gap;
}

TEST(LocalPose, ComposedAgainItGivesBackWhatIsDrawn) {
  const Skeleton& sk = defaultCharacter().skeleton;
  const BakedPalette& p = defaultPalette();
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(test::defaultCrowdDesc()).isOk());
  LayerMask arm;
  uint32_t mask = 0;
  ASSERT_TRUE(buildLayerMask(sk, p, "right arm", {"r_clavicle"}, &arm).isOk());
  ASSERT_TRUE(crowd.addLayerMask(arm, &mask).isOk());
  const uint32_t walk = uint32_t(p.findClip("walk")), run = uint32_t(p.findClip("run"));
  InstanceDesc d;
  d.position = glm::dvec3(4, 0, -3);
  d.rotation = glm::angleAxis(0.8f, glm::vec3(0, 1, 0));
  d.scale = 1.3f;
  d.clip = walk;
  d.time_seconds = 0.35;  // On a frame of the 30 Hz bake after the update below.
  InstanceHandle plain, between, fading, layered;
  ASSERT_TRUE(crowd.add(d, &plain).isOk());
  d.time_seconds = 0.37;  // Between two frames: their rows lerped.
  ASSERT_TRUE(crowd.add(d, &between).isOk());
  ASSERT_TRUE(crowd.add(d, &fading).isOk());
  ASSERT_TRUE(crowd.add(d, &layered).isOk());
  ASSERT_TRUE(crowd.crossfade(fading, run, 0.5).isOk());
  ASSERT_TRUE(crowd.playOverlay(layered, uint32_t(p.findClip("wave")), mask, 0.8f, 0.0).isOk());
  ASSERT_TRUE(crowd.update(0.25, test::testCamera({0, 1.6, 10}, {4, 1, -3})).isOk());
  glm::dmat4 world = glm::mat4_cast(glm::dquat(d.rotation)) * double(d.scale);
  world[3] = glm::dvec4(d.position, 1.0);

  const double height = double(p.character_height);
  // Bounds: rounding on a frame; what the lerped rows' shear costs between frames, with an
  // overlay and crossfading (measured: 0.001, 5.1, 5.1 and 844 millionths of the height).
  for (const auto& [h, name, bound] :
       {std::tuple{plain, "on a frame", 1e-7}, std::tuple{between, "between frames", 2e-5},
        std::tuple{layered, "with an overlay", 2e-5}, std::tuple{fading, "crossfading", 2e-3}}) {
    SCOPED_TRACE(name);
    std::vector<TransformD> local(sk.jointCount());
    ASSERT_TRUE(crowd.localPose(h, sk, local).isOk());
    std::vector<glm::dmat4> model(local.size()), skinning(local.size());
    ASSERT_TRUE(composePose(sk, local, model, skinning).isOk());
    const double gap = largestGap(crowd, h, world, skinning);
    std::printf(
        "localPose %s: composed again, %.3g units (%.3g of the height) from the drawn pose\n", name,
        gap, gap / height);
    EXPECT_LT(gap / height, bound);
    // Joints the palette leaves out (the root): their rest transform.
    for (uint32_t j = 0; j < sk.jointCount(); ++j) {
      if (p.skeleton_to_palette[j] >= 0) continue;
      const TransformD rest = TransformD::fromFloat(sk.rest_pose[j]);
      EXPECT_LT(glm::length(local[j].translation - rest.translation), 1e-12) << j;
      EXPECT_NEAR(std::abs(glm::dot(local[j].rotation, glm::normalize(rest.rotation))), 1.0, 1e-12);
    }
  }
}

TEST(LocalPose, ALookAtTurnsTheHeadOfTheDrawnPoseAndNothingElse) {
  const Skeleton& sk = defaultCharacter().skeleton;
  const BakedPalette& p = defaultPalette();
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(test::defaultCrowdDesc()).isOk());
  InstanceDesc d;
  d.clip = uint32_t(p.findClip("walk"));
  d.time_seconds = 0.6;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  std::vector<TransformD> pose(sk.jointCount());
  ASSERT_TRUE(crowd.localPose(h, sk, pose).isOk());
  std::vector<glm::dmat4> model0(pose.size()), skin0(pose.size()), model1(pose.size()),
      skin1(pose.size());
  ASSERT_TRUE(composePose(sk, pose, model0, skin0).isOk());
  const uint32_t neck = uint32_t(sk.findJoint("neck")), head = uint32_t(sk.findJoint("head"));
  LookAt look;
  look.chain = {{neck, 0.4, glm::radians(40.0)}, {head, 1.0, glm::radians(60.0)}};
  const glm::dvec3 target = glm::dvec3(model0[head][3]) + glm::dvec3(1.5, 0.3, 2.0);
  ASSERT_TRUE(applyLookAt(sk, look, target, pose).isOk());
  ASSERT_TRUE(composePose(sk, pose, model1, skin1).isOk());
  const auto forward = [&](const std::vector<glm::dmat4>& m) {
    return glm::normalize(glm::dmat3(m[head]) *
                          (glm::dmat3(glm::dmat4(sk.inverse_bind_matrices[head])) * look.forward));
  };
  const glm::dvec3 to = glm::normalize(target - glm::dvec3(model1[head][3]));
  EXPECT_GT(glm::dot(forward(model1), to), glm::dot(forward(model0), to) + 0.1);
  EXPECT_GT(glm::dot(forward(model1), to), 1.0 - 1e-9);  // Within both limits: straight at it.
  // Joints off the chain keep their matrices.
  for (const char* off : {"pelvis", "l_thigh", "r_foot", "chest", "l_hand"}) {
    const uint32_t j = uint32_t(sk.findJoint(off));
    for (int c = 0; c < 4; ++c) EXPECT_EQ(skin1[j][c], skin0[j][c]) << off;
  }
}

TEST(LocalPose, BadCallsAreRefusedByName) {
  const Skeleton& sk = defaultCharacter().skeleton;
  CrowdManager crowd;
  std::vector<TransformD> pose(sk.jointCount());
  InstanceHandle h;
  EXPECT_EQ(crowd.localPose(h, sk, pose).code(), StatusCode::kNotFound);  // No init().
  ASSERT_TRUE(crowd.init(test::defaultCrowdDesc()).isOk());
  InstanceDesc d;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  std::vector<TransformD> short_pose(sk.jointCount() - 1);
  EXPECT_EQ(crowd.localPose(h, sk, short_pose).code(), StatusCode::kCountMismatch);
  Skeleton other = sk;
  other.parents.pop_back(), other.joint_names.pop_back(), other.rest_pose.pop_back();
  other.inverse_bind_matrices.pop_back();
  const Status s = crowd.localPose(h, other, short_pose);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("palette was baked from one of"), std::string::npos) << s.message();
  ASSERT_TRUE(crowd.remove(h).isOk());
  EXPECT_EQ(crowd.localPose(h, sk, pose).code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace si
