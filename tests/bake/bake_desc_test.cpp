// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include "bake/bake_test_helpers.h"
#include "si/bake/bake_desc.h"
#include "si/core/default_character.h"

namespace si {
namespace {

TEST(PlanFrames, EndsExactlyOnTheClipEnd) {
  const FramePlan p = planFrames(1.0, 30.0);
  EXPECT_EQ(p.frame_count, 31u);
  EXPECT_DOUBLE_EQ(p.frame_interval_seconds * (p.frame_count - 1), 1.0);
  // 0.66 s at 30 Hz: 19.8 intervals round up to 20, so frames are slightly closer than 1/30.
  const FramePlan q = planFrames(0.66, 30.0);
  EXPECT_EQ(q.frame_count, 21u);
  EXPECT_DOUBLE_EQ(q.frame_interval_seconds * 20, 0.66);
}

TEST(PlanFrames, ZeroLengthAndTinyClips) {
  EXPECT_EQ(planFrames(0.0, 30.0).frame_count, 1u);
  EXPECT_EQ(planFrames(0.0, 30.0).frame_interval_seconds, 0.0);
  EXPECT_EQ(planFrames(1e-6, 30.0).frame_count, 2u);
  EXPECT_EQ(planFrames(2.0, 0.0).frame_count, 1u);
}

class PlanPaletteTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(makeDefaultCharacter({}, &character_).isOk()); }
  Character character_;
};

TEST_F(PlanPaletteTest, DefaultsBakeEveryClipAt30Hz) {
  PalettePlan plan;
  ASSERT_TRUE(planPalette(character_, {}, &plan).isOk());
  ASSERT_EQ(plan.clip_indices.size(), character_.clips.size());
  EXPECT_EQ(plan.layout.joint_stride_texels, 4u);
  // Every joint but the unweighted root is stored.
  EXPECT_EQ(plan.palette_joints.size(), character_.skeleton.jointCount() - 1);
  EXPECT_EQ(plan.palette_joints[0], uint32_t(character_.skeleton.findJoint("pelvis")));
  EXPECT_EQ(plan.layout.frame_stride_texels, plan.palette_joints.size() * 4);
  uint64_t frames = 0;
  for (const FramePlan& f : plan.frames) frames += f.frame_count;
  EXPECT_EQ(plan.layout.used_texel_count, frames * plan.palette_joints.size() * 4);
  EXPECT_EQ(plan.texture_bytes, plan.layout.textureTexelCount() * 16);
}

TEST_F(PlanPaletteTest, FormatsAndClipSelection) {
  BakeDesc d;
  d.format = PaletteFormat::kMatrix3x4F16;
  d.clip_names = {"run", "idle"};
  PalettePlan plan;
  ASSERT_TRUE(planPalette(character_, d, &plan).isOk());
  ASSERT_EQ(plan.clip_indices.size(), 2u);
  EXPECT_EQ(plan.clip_indices[0], uint32_t(character_.findClip("run")));
  EXPECT_EQ(plan.texture_bytes, plan.layout.textureTexelCount() * 8);
  d.format = PaletteFormat::kQuatTranslationF32;
  ASSERT_TRUE(planPalette(character_, d, &plan).isOk());
  EXPECT_EQ(plan.layout.texels_per_joint, 2u);
  EXPECT_EQ(plan.layout.joint_stride_texels, 2u);
}

TEST_F(PlanPaletteTest, PerClipRates) {
  const double rates[] = {10.0, 60.0, 30.0, 15.0};
  PalettePlan plan;
  ASSERT_TRUE(planPalette(character_, {}, &plan, rates).isOk());
  ASSERT_EQ(plan.frames.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(plan.frames[i].frame_count,
              planClipFrames(character_.clips[plan.clip_indices[i]], rates[i]).frame_count);
  }
}

TEST_F(PlanPaletteTest, ValidityMatrix) {
  PalettePlan plan;
  EXPECT_EQ(planPalette(character_, {}, nullptr).code(), StatusCode::kInvalidArgument);
  BakeDesc d;
  d.sample_rate_hz = -1.0f;
  EXPECT_EQ(planPalette(character_, d, &plan).code(), StatusCode::kInvalidArgument);
  d = BakeDesc();
  d.format = static_cast<PaletteFormat>(42);
  EXPECT_EQ(planPalette(character_, d, &plan).code(), StatusCode::kInvalidArgument);
  d = BakeDesc();
  d.clip_names = {"dance"};
  EXPECT_EQ(planPalette(character_, d, &plan).code(), StatusCode::kNotFound);
  d = BakeDesc();
  d.max_texture_size = 16;
  EXPECT_EQ(planPalette(character_, d, &plan).code(), StatusCode::kLimitExceeded);
  d = BakeDesc();
  d.sample_rate_hz = 1e9f;
  EXPECT_EQ(planPalette(character_, d, &plan).code(), StatusCode::kLimitExceeded);
  const double one_rate[] = {30.0};
  EXPECT_EQ(planPalette(character_, {}, &plan, one_rate).code(), StatusCode::kInvalidArgument);
  d = BakeDesc();
  d.rate_mode = static_cast<RateMode>(9);
  EXPECT_EQ(planPalette(character_, d, &plan).code(), StatusCode::kInvalidArgument);
  Character no_clips = character_;
  no_clips.clips.clear();
  EXPECT_EQ(planPalette(no_clips, {}, &plan).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(plan.clip_indices.empty());  // Untouched by every failure.
}

// A hostile clip (an hour long, 16 joints, 240 Hz: 0.9 GiB of texels) is refused by the byte
// limit while planning, before anything is allocated; raising the limit admits it.
TEST(PalettePlanning, PalettesPastTheByteLimitAreRefusedBeforeAllocating) {
  Character c = test::chainCharacter(16);
  c.clips.push_back(test::blankClip(c, "hour", 3600.0f));
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = 240.0f;
  PalettePlan plan;
  const Status s = planPalette(c, d, &plan);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("max_palette_bytes 536870912"), std::string::npos) << s.message();
  EXPECT_TRUE(plan.clip_indices.empty());
  d.max_palette_bytes = uint64_t(2) << 30;
  ASSERT_TRUE(planPalette(c, d, &plan).isOk());
  EXPECT_GT(plan.texture_bytes, uint64_t(512) << 20);
  // And a small limit refuses a small bake, naming its size.
  d = BakeDesc();
  d.max_palette_bytes = 1024;
  BakedPalette p;
  const Status small = bakePalette(c, d, &p, nullptr);
  EXPECT_EQ(small.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(small.message().find("more than BakeDesc.max_palette_bytes 1024"), std::string::npos);
  EXPECT_TRUE(p.clips.empty());
}

// The work limit: a small palette can hide a long evaluation (many joints or vertices per
// frame); it is refused while planning, naming the count, and a larger limit admits it.
TEST(PalettePlanning, BakesPastTheWorkLimitAreRefusedBeforeEvaluating) {
  Character c = test::chainCharacter(40);
  c.clips.push_back(test::blankClip(c, "minute", 60.0f));
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.max_evaluations = 100000;  // 1801 frames x (40 joints + 164 vertices) = 367,404.
  PalettePlan plan;
  const Status s = planPalette(c, d, &plan);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("1801 frames x (40 joints + 164 vertices) = 367404 evaluations"),
            std::string::npos) << s.message();
  d.max_evaluations = 367404;
  EXPECT_TRUE(planPalette(c, d, &plan).isOk());
}

}  // namespace
}  // namespace si
