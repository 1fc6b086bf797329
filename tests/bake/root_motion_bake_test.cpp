// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Root motion in the baker: clips baked in place with their motion sampled per frame, measured
// against the reference, and the in-place palette plus the motion giving back the travelling
// character.
#include <gtest/gtest.h>

#include "bake/bake_test_helpers.h"
#include "si/bake/animation_baker.h"
#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"

namespace si {
namespace {

using test::kPi;

Character movingCharacter() { return test::travellingCharacter(); }

struct Baked {
  BakedPalette palette;
  BakeReport report;
};

BakeDesc fixedRate() {
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;  // 30 Hz: the automatic search is slow under sanitizers.
  return d;
}

Baked bake(const Character& c, const BakeDesc& d = fixedRate()) {
  Baked b;
  const Status s = bakePalette(c, d, &b.palette, &b.report);
  EXPECT_TRUE(s.isOk()) << s.toString();
  return b;
}

// The moving character baked once for the tests that only read it.
const Baked& movingBake() {
  static const Baked b = bake(movingCharacter());
  return b;
}

TEST(RootMotionBake, ClipsMarkedForItCarryTheirMotionAndTheOthersNone) {
  const Character c = movingCharacter();
  const Baked& b = movingBake();
  ASSERT_TRUE(b.palette.validate().isOk());
  for (size_t i = 0; i < b.palette.clips.size(); ++i) {
    const BakedClip& clip = b.palette.clips[i];
    SCOPED_TRACE(clip.name);
    const bool moving = c.clips[i].root_motion.extract;
    EXPECT_EQ(clip.root_motion.size(), moving ? clip.frame_count : 0u);
    EXPECT_EQ(b.report.clips[i].root_motion_joint, moving ? "root" : "");
    if (!moving) {
      EXPECT_EQ(summarizeRootMotion(clip).average_speed, 0.0);
      continue;
    }
    EXPECT_EQ(clip.root_motion[0], glm::vec3(0.0f));
    // The baked motion against the reference, at the report's own times: small.
    EXPECT_LT(b.report.clips[i].root_motion_max_error_ratio, 1e-3);
    EXPECT_NEAR(b.report.clips[i].root_motion_max_error_ratio,
                b.report.clips[i].root_motion_max_error_units / double(c.height()), 1e-12);
  }
  const BakedClip& walk = b.palette.clips[size_t(b.palette.findClip("walk_forward"))];
  const BakedClip& turn = b.palette.clips[size_t(b.palette.findClip("walk_turn_left"))];
  const RootMotionSummary w = summarizeRootMotion(walk), t = summarizeRootMotion(turn);
  EXPECT_NEAR(w.average_speed, 1.3, 1e-5);
  EXPECT_NEAR(w.average_velocity.x, 0.0, 1e-6);
  EXPECT_NEAR(w.average_yaw_rate, 0.0, 1e-6);
  EXPECT_NEAR(t.average_yaw_rate, kPi / 4, 1e-5);
  EXPECT_NEAR(t.whole_clip.translation.y, std::sin(kPi / 4) / (kPi / 4), 1e-5);
  // The circle's samples are lerped along chords: an error that falls as the rate rises.
  const size_t turn_index = size_t(b.palette.findClip("walk_turn_left"));
  BakeDesc fine = fixedRate();
  fine.sample_rate_hz = 120.0f;
  fine.clip_names = {"walk_turn_left"};
  const Baked finer = bake(c, fine);
  EXPECT_GT(b.report.clips[turn_index].root_motion_max_error_units, 0.0);
  EXPECT_LT(finer.report.clips[0].root_motion_max_error_units,
            0.5 * b.report.clips[turn_index].root_motion_max_error_units);
}

// The in-place bake stays on the spot: its culling box is the walk's; baked with the motion in
// its poses, the box reaches past the walk's by most of the 1.3 units the root travels.
TEST(RootMotionBake, InPlaceClipsHaveInPlaceBounds) {
  Character c = movingCharacter();
  const Baked& in_place = movingBake();
  for (Clip& clip : c.clips) clip.root_motion.extract = false;
  const Baked travelling = bake(c);
  const auto box = [](const Baked& b, const char* name) {
    return b.palette.clips[size_t(b.palette.findClip(name))].bounds;
  };
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(box(in_place, "walk_forward").min[k], box(in_place, "walk").min[k], 1e-4) << k;
    EXPECT_NEAR(box(in_place, "walk_forward").max[k], box(in_place, "walk").max[k], 1e-4) << k;
  }
  EXPECT_GT(box(travelling, "walk_forward").max.z, box(in_place, "walk").max.z + 0.9f);
  EXPECT_TRUE(travelling.palette.clips[size_t(travelling.palette.findClip("walk_forward"))]
                  .root_motion.empty());
}

// What the crowd draws, emulated: the in-place palette placed by the baked motion equals the
// reference pose with the motion in it, within the bake's error plus the motion's.
TEST(RootMotionBake, InPlacePosesPlacedByTheMotionAreTheTravellingPoses) {
  const Character c = movingCharacter();
  const Baked& b = movingBake();
  std::vector<glm::mat4> emulated(c.skeleton.jointCount());
  std::vector<glm::vec3> drawn(c.mesh.vertexCount());
  std::vector<glm::dvec3> reference(c.mesh.vertexCount());
  ReferencePose pose;
  for (const char* name : {"walk_forward", "walk_turn_left"}) {
    SCOPED_TRACE(name);
    const uint32_t ci = uint32_t(b.palette.findClip(name));
    const BakedClip& clip = b.palette.clips[ci];
    Clip moving = c.clips[ci];
    moving.root_motion.extract = false;
    const ClipErrorReport& r = b.report.clips[ci];
    const double bound = r.max_error_units + r.root_motion_max_error_units;
    double worst = 0.0;
    for (double t = 0.0; t <= clip.duration_seconds; t += 0.0371) {
      ASSERT_TRUE(emulateSkinningMatrices(b.palette, ci, sampleFrames(clip, t), emulated).isOk());
      ASSERT_TRUE(emulateSkinning(c.mesh, emulated, drawn, {}).isOk());
      ASSERT_TRUE(evaluateLocalPose(c.skeleton, moving, t, &pose).isOk());
      ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, reference, {}, {}).isOk());
      const glm::dmat4 place = groundMotionMatrix(rootMotionAt(clip, t));
      for (size_t v = 0; v < drawn.size(); ++v)
        worst = std::max(worst, glm::length(glm::dvec3(place * glm::dvec4(glm::dvec3(drawn[v]), 1.0)) -
                                            reference[v]));
    }
    EXPECT_LE(worst, bound * 1.01 + 1e-6);
    EXPECT_GT(worst, 0.0);
  }
}

TEST(RootMotionBake, PalettesRefuseBrokenMotionSamples) {
  const Baked& b = movingBake();
  const uint32_t ci = uint32_t(b.palette.findClip("walk_turn_left"));
  const auto broken = [&](auto change) {
    BakedPalette p = b.palette;
    change(p.clips[ci].root_motion);
    return p.validate();
  };
  EXPECT_EQ(broken([](std::vector<glm::vec3>& m) { m.pop_back(); }).code(),
            StatusCode::kCountMismatch);
  EXPECT_EQ(broken([](std::vector<glm::vec3>& m) { m[3].x = NAN; }).code(), StatusCode::kNotFinite);
  EXPECT_EQ(broken([](std::vector<glm::vec3>& m) { m[0].y = 0.5f; }).code(),
            StatusCode::kOutOfRange);
  const Status jump = broken([](std::vector<glm::vec3>& m) { m[5].z += 7.0f; });
  EXPECT_EQ(jump.code(), StatusCode::kOutOfRange);
  EXPECT_NE(jump.message().find("unwrapped"), std::string::npos) << jump.message();
  EXPECT_TRUE(broken([](std::vector<glm::vec3>& m) { m.clear(); }).isOk());  // None at all.
}

// A clip turning several times round within one cycle: the samples unwrap the yaw past pi, so
// lerping between them never takes the long way round.
TEST(RootMotionBake, FastTurnsUnwrapTheYaw) {
  Character c = test::chainCharacter(2);
  Clip spin = test::blankClip(c, "spin", 1.0f, LoopMode::kLoop);
  spin.root_motion.extract = true;
  QuatTrack& rot = spin.joint_tracks[0].rotation;
  for (int k = 0; k <= 40; ++k) {
    rot.times_seconds.push_back(float(k) / 40.0f);
    rot.values.push_back(test::axisAngleF(3 * 2 * kPi * k / 40.0, {0, 1, 0}));
  }
  c.clips.push_back(spin);
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = 40.0f;
  const Baked b = bake(c, d);
  const RootMotionSummary s = summarizeRootMotion(b.palette.clips[0]);
  EXPECT_NEAR(s.whole_clip.yaw, 6 * kPi, 1e-4);  // Three whole turns.
  EXPECT_LT(b.report.clips[0].root_motion_max_error_ratio, 1e-5);
}

}  // namespace
}  // namespace si
