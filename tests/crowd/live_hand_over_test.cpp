// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The hand-over between an instance's clip and a live pose (setLivePose and clearLivePose with
// a blend): the record blends the live frame with the clip at the clip's weight, jointMatrix
// answers with the same blend, no step jumps, the frame is freed when the clip is back in, and
// handing back and forth goes on from where the blend is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "bake/bake_test_helpers.h"
#include "crowd/crowd_test_helpers.h"
#include "crowd/live_pose_helpers.h"
#include "si/core/reference_evaluator.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using test::defaultCharacter;
using test::defaultPalette;
using test::enginePose;
using test::liveDesc;
using test::recordOf;

const Camera& camera() {
  static const Camera c = test::testCamera({0, 1.6, 6}, {0, 1, 0});
  return c;
}

float floatOf(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

// Every palette joint's matrix of `h` as jointMatrix gives it.
std::vector<glm::dmat4> drawnJoints(const CrowdManager& crowd, InstanceHandle h) {
  const BakedPalette& p = defaultPalette();
  std::vector<glm::dmat4> out(p.palette_joints.size());
  for (size_t k = 0; k < out.size(); ++k)
    EXPECT_TRUE(crowd.jointMatrix(h, p.palette_joints[k], &out[k]).isOk());
  return out;
}

// The largest distance between the joints' origins of two poses, model units.
double largestMove(const std::vector<glm::dmat4>& a, const std::vector<glm::dmat4>& b) {
  double d = 0.0;
  for (size_t k = 0; k < a.size(); ++k)
    d = std::max(d, glm::length(glm::dvec3(a[k][3]) - glm::dvec3(b[k][3])));
  return d;
}

// A posed instance and its twin playing the same clip from the same time, at the origin.
struct Pair {
  CrowdManager crowd;
  InstanceHandle posed, playing;
  explicit Pair(uint32_t capacity = 1) {
    EXPECT_TRUE(crowd.init(liveDesc(capacity)).isOk());
    InstanceDesc d;
    d.clip = uint32_t(defaultPalette().findClip("walk"));
    d.time_seconds = 0.3;
    EXPECT_TRUE(crowd.add(d, &posed).isOk());
    EXPECT_TRUE(crowd.add(d, &playing).isOk());
  }
};

TEST(LiveHandOver, TheRecordBlendsThePoseWithTheClipAndTheFrameIsFreedAtTheEnd) {
  const BakedPalette& p = defaultPalette();
  const std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, p);
  Pair pair;
  CrowdManager& crowd = pair.crowd;
  const uint32_t live_first = CrowdExport(crowd).livePoseFirstTexel();
  ASSERT_TRUE(crowd.setLivePose(pair.posed, pose, 0.4).isOk());
  ASSERT_TRUE(crowd.update(0.1, camera()).isOk());  // A quarter in: the clip weighs 0.75.
  const InstanceRecord* rec = recordOf(crowd, pair.posed);
  const InstanceRecord* twin = recordOf(crowd, pair.playing);
  ASSERT_TRUE(rec != nullptr && twin != nullptr);
  EXPECT_EQ(rec->frames[0], live_first);
  EXPECT_EQ(rec->frames[1], live_first);
  EXPECT_EQ(rec->frames[2], twin->frames[2]);  // Clip B: the clip as the twin plays it.
  EXPECT_EQ(rec->frames[3], twin->frames[3]);
  EXPECT_EQ(rec->blend[1], twin->blend[1]);
  EXPECT_NEAR(floatOf(rec->blend[2]), 0.75f, 1e-6f);
  // jointMatrix: the same blend of the live pose and the clip.
  std::vector<glm::dmat4> drawn = drawnJoints(crowd, pair.posed);
  std::vector<glm::dmat4> clip = drawnJoints(crowd, pair.playing);
  for (size_t k = 0; k < pose.size(); ++k)
    for (int c = 0; c < 4; ++c)
      EXPECT_LT(glm::length(drawn[k][c] - (glm::dvec4(pose[k][c]) * 0.25 + clip[k][c] * 0.75)),
                1e-5)
          << k;
  // Past the blend: the live pose alone.
  ASSERT_TRUE(crowd.update(0.4, camera()).isOk());
  rec = recordOf(crowd, pair.posed);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(rec->frames[k], live_first);
  EXPECT_EQ(rec->blend[2], 0u);
  // Back to the clip over 0.2 s: the frame is held (no other instance can take it) until the
  // clip is wholly in, then freed, and the record is the twin's again.
  ASSERT_TRUE(crowd.clearLivePose(pair.posed, 0.2).isOk());
  ASSERT_TRUE(crowd.update(0.1, camera()).isOk());
  rec = recordOf(crowd, pair.posed);
  EXPECT_EQ(rec->frames[0], live_first);
  EXPECT_NEAR(floatOf(rec->blend[2]), 0.5f, 1e-6f);
  EXPECT_EQ(crowd.setLivePose(pair.playing, pose).code(), StatusCode::kLimitExceeded);
  ASSERT_TRUE(crowd.update(0.15, camera()).isOk());
  rec = recordOf(crowd, pair.posed);
  twin = recordOf(crowd, pair.playing);
  EXPECT_EQ(std::memcmp(rec, twin, sizeof(InstanceRecord)), 0);
  EXPECT_TRUE(crowd.setLivePose(pair.playing, pose).isOk());  // The frame is free again.
}

// Stepping at 60 Hz through a half-second hand-over to a still pose and back: no step moves a
// joint more than the clip's own step plus the blend's share of the distance between the pose
// and the clip (dt / blend of it); without a blend the first step jumps the whole distance.
TEST(LiveHandOver, NoStepJumps) {
  const BakedPalette& p = defaultPalette();
  const std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, p);
  const double dt = 1.0 / 60.0;
  const double height = double(p.character_height);
  for (const double blend : {0.5, 0.0}) {
    Pair pair;
    CrowdManager& crowd = pair.crowd;
    ASSERT_TRUE(crowd.update(0.0, camera()).isOk());
    std::vector<glm::dmat4> last = drawnJoints(crowd, pair.posed);
    std::vector<glm::dmat4> last_clip = drawnJoints(crowd, pair.playing);
    double worst_excess = -1e9, worst_step = 0.0, worst_clip_step = 0.0;
    for (int step = 0; step < 80; ++step) {
      if (step == 0) {
        ASSERT_TRUE(crowd.setLivePose(pair.posed, pose, blend).isOk());
      }
      if (step == 40) {
        ASSERT_TRUE(crowd.clearLivePose(pair.posed, blend).isOk());
      }
      ASSERT_TRUE(crowd.update(dt, camera()).isOk());
      const std::vector<glm::dmat4> now = drawnJoints(crowd, pair.posed);
      const std::vector<glm::dmat4> clip = drawnJoints(crowd, pair.playing);
      const double clip_step = largestMove(clip, last_clip);
      const double step_move = largestMove(now, last);
      // The blend's share of the distance between the live pose and the clip.
      std::vector<glm::dmat4> live(pose.size());
      for (size_t k = 0; k < pose.size(); ++k) live[k] = glm::dmat4(pose[k]);
      const double share = blend > 0.0 ? largestMove(live, last_clip) * dt / blend : 0.0;
      worst_excess = std::max(worst_excess, step_move - (clip_step + share));
      worst_step = std::max(worst_step, step_move);
      worst_clip_step = std::max(worst_clip_step, clip_step);
      last = now;
      last_clip = clip;
    }
    std::printf("blend %.2f s: largest step %.4g of the height, the clip's own %.4g\n", blend,
                worst_step / height, worst_clip_step / height);
    if (blend > 0.0)
      EXPECT_LE(worst_excess, 1e-6 * height);
    else
      EXPECT_GT(worst_excess, 0.05 * height);  // The measure sees a pop.
  }
}

// Handing back while the pose fades in (or in again while it fades out) goes on from the
// weight the blend has: nothing moves at the call.
TEST(LiveHandOver, BackAndForthGoesOnFromWhereTheBlendIs) {
  const BakedPalette& p = defaultPalette();
  const std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, p);
  Pair pair;
  CrowdManager& crowd = pair.crowd;
  ASSERT_TRUE(crowd.setLivePose(pair.posed, pose, 0.5).isOk());
  ASSERT_TRUE(crowd.update(0.3, camera()).isOk());
  std::vector<glm::dmat4> before = drawnJoints(crowd, pair.posed);
  EXPECT_NEAR(floatOf(recordOf(crowd, pair.posed)->blend[2]), 0.4f, 1e-6f);
  ASSERT_TRUE(crowd.clearLivePose(pair.posed, 0.5).isOk());
  EXPECT_LT(largestMove(drawnJoints(crowd, pair.posed), before), 1e-9);
  ASSERT_TRUE(crowd.update(0.2, camera()).isOk());  // Live 0.6 -> 0.6 - 0.6 * 0.4 = 0.36.
  EXPECT_NEAR(floatOf(recordOf(crowd, pair.posed)->blend[2]), 0.64f, 1e-6f);
  before = drawnJoints(crowd, pair.posed);
  ASSERT_TRUE(crowd.setLivePose(pair.posed, pose, 0.5).isOk());
  EXPECT_LT(largestMove(drawnJoints(crowd, pair.posed), before), 1e-9);
  ASSERT_TRUE(crowd.update(0.25, camera()).isOk());  // 0.36 -> 0.36 + 0.64 * 0.5 = 0.68.
  EXPECT_NEAR(floatOf(recordOf(crowd, pair.posed)->blend[2]), 0.32f, 1e-6f);
  // A pose set again while it fades in changes the pose, not the blend.
  ASSERT_TRUE(crowd.setLivePose(pair.posed, pose, 5.0).isOk());
  ASSERT_TRUE(crowd.update(0.125, camera()).isOk());  // 0.68 -> 0.84.
  EXPECT_NEAR(floatOf(recordOf(crowd, pair.posed)->blend[2]), 0.16f, 1e-6f);
}

TEST(LiveHandOver, BadBlendsAreRefusedByName) {
  const std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, defaultPalette());
  Pair pair;
  for (const double bad : {-0.1, double(std::nanf("")), 1.0 / 0.0}) {
    Status s = pair.crowd.setLivePose(pair.posed, pose, bad);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(s.message().find("setLivePose: blend_seconds"), std::string::npos) << s.message();
    s = pair.crowd.clearLivePose(pair.posed, bad);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(s.message().find("clearLivePose: blend_seconds"), std::string::npos) << s.message();
  }
  EXPECT_EQ(CrowdExport(pair.crowd).livePoseTexels().size() > 0, true);
  ASSERT_TRUE(pair.crowd.update(0.0, camera()).isOk());  // Nothing was taken.
  EXPECT_LT(recordOf(pair.crowd, pair.posed)->frames[0],
            CrowdExport(pair.crowd).livePoseFirstTexel());
}

// si::paletteSkinning: composePose's matrices, one per skeleton joint, become the palette's
// slots that setLivePose takes; a pose of local transforms so drawn is what jointMatrix gives.
TEST(LiveHandOver, PaletteSkinningTakesTheComposedPoseToTheCrowd) {
  const Skeleton& sk = defaultCharacter().skeleton;
  const BakedPalette& p = defaultPalette();
  Pair pair;
  std::vector<TransformD> local(sk.jointCount());
  ASSERT_TRUE(pair.crowd.localPose(pair.playing, sk, local).isOk());
  local[1].rotation = glm::angleAxis(0.7, glm::dvec3(1, 0, 0)) * local[1].rotation;
  std::vector<glm::dmat4> model(local.size()), skinning(local.size());
  ASSERT_TRUE(composePose(sk, local, model, skinning).isOk());
  std::vector<glm::mat4> slots(p.palette_joints.size());
  ASSERT_TRUE(paletteSkinning(p, skinning, slots).isOk());
  ASSERT_TRUE(pair.crowd.setLivePose(pair.posed, slots).isOk());
  for (uint32_t k = 0; k < slots.size(); ++k) {
    glm::dmat4 m;
    ASSERT_TRUE(pair.crowd.jointMatrix(pair.posed, p.palette_joints[k], &m).isOk());
    for (int c = 0; c < 4; ++c)
      EXPECT_LT(glm::length(m[c] - skinning[p.palette_joints[k]][c]), 1e-6) << k;
  }
  const Status s = paletteSkinning(p, Span<const glm::dmat4>(skinning.data(), 2), slots);
  EXPECT_EQ(s.code(), StatusCode::kCountMismatch);
  EXPECT_NE(s.message().find("paletteSkinning: 2 skinning matrices"), std::string::npos)
      << s.message();
  EXPECT_EQ(paletteSkinning(p, skinning, Span<glm::mat4>(slots.data(), 1)).code(),
            StatusCode::kCountMismatch);
}

}  // namespace
}  // namespace si
