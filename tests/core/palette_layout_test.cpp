// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include <set>

#include "si/core/palette_layout.h"

namespace si {
namespace {

PaletteLayoutDesc desc(const std::vector<uint32_t>& frames, uint32_t joints = 22) {
  PaletteLayoutDesc d;
  d.joint_count = joints;
  d.clip_frame_counts = frames;
  d.texels_per_joint = 3;
  return d;
}

TEST(PaletteLayout, ValidityMatrix) {
  PaletteLayout out;
  EXPECT_EQ(computePaletteLayout(PaletteLayoutDesc(), &out).code(), StatusCode::kInvalidArgument);
  const std::vector<uint32_t> frames = {30, 31};
  EXPECT_TRUE(computePaletteLayout(desc(frames), &out).isOk());
  EXPECT_EQ(computePaletteLayout(desc(frames), nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(computePaletteLayout(desc(frames, 0), &out).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(computePaletteLayout(desc({}), &out).code(), StatusCode::kInvalidArgument);
  const std::vector<uint32_t> zero = {30, 0};
  EXPECT_EQ(computePaletteLayout(desc(zero), &out).code(), StatusCode::kInvalidArgument);
  PaletteLayoutDesc d = desc(frames);
  d.texels_per_joint = 5;
  EXPECT_EQ(computePaletteLayout(d, &out).code(), StatusCode::kInvalidArgument);
  d = desc(frames);
  d.joint_stride_texels = 2;
  EXPECT_EQ(computePaletteLayout(d, &out).code(), StatusCode::kInvalidArgument);
  d = desc(frames);
  d.max_texture_size = 1000;
  EXPECT_EQ(computePaletteLayout(d, &out).code(), StatusCode::kInvalidArgument);
}

TEST(PaletteLayout, DefaultStrideIsPowerOfTwoAndJointsNeverStraddleRows) {
  const std::vector<uint32_t> frames = {30, 31, 7};
  PaletteLayout l;
  ASSERT_TRUE(computePaletteLayout(desc(frames), &l).isOk());
  EXPECT_EQ(l.joint_stride_texels, 4u);
  EXPECT_EQ(l.width, 1u << l.width_log2);
  EXPECT_LE(l.height, l.width);
  std::set<uint32_t> seen;
  for (uint32_t c = 0; c < 3; ++c)
    for (uint32_t f = 0; f < frames[c]; ++f)
      for (uint32_t j = 0; j < 22; ++j) {
        const glm::uvec2 first = l.texelCoord(l.texelIndex(c, f, j, 0));
        for (uint32_t r = 0; r < 3; ++r) {
          const uint32_t i = l.texelIndex(c, f, j, r);
          EXPECT_TRUE(seen.insert(i).second) << "texel reused";
          const glm::uvec2 xy = l.texelCoord(i);
          ASSERT_LT(xy.x, l.width);
          ASSERT_LT(xy.y, l.height);
          EXPECT_EQ(xy.y, first.y);  // Same row for all of a joint's texels.
          EXPECT_EQ(xy.x, first.x + r);
        }
      }
  EXPECT_EQ(l.used_texel_count, uint64_t(68) * 22 * 4);
}

TEST(PaletteLayout, TightStrideUsesAQuarterLessMemory) {
  const std::vector<uint32_t> frames = {1000};
  PaletteLayoutDesc d = desc(frames, 64);
  PaletteLayout wide, tight;
  ASSERT_TRUE(computePaletteLayout(d, &wide).isOk());
  d.joint_stride_texels = 3;
  ASSERT_TRUE(computePaletteLayout(d, &tight).isOk());
  EXPECT_EQ(tight.used_texel_count * 4, wide.used_texel_count * 3);
}

TEST(PaletteLayout, FailsClearlyWhenTheTextureLimitIsTooSmall) {
  const std::vector<uint32_t> frames = {36000};  // 10 minutes at 60 fps.
  PaletteLayoutDesc d = desc(frames, 1024);
  d.max_texture_size = 4096;
  PaletteLayout l;
  const Status s = computePaletteLayout(d, &l);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("4096x4096"), std::string::npos) << s.message();
  EXPECT_EQ(l.width, 0u);  // Untouched.
}

TEST(PaletteLayout, ManyJointsFitWithinTheLimit) {
  const std::vector<uint32_t> frames = {60};
  PaletteLayoutDesc d = desc(frames, 1024);
  d.max_texture_size = 1024;
  PaletteLayout l;
  ASSERT_TRUE(computePaletteLayout(d, &l).isOk());
  EXPECT_LE(l.width, 1024u);
  EXPECT_LE(l.height, 1024u);
  EXPECT_GE(l.textureTexelCount(), l.used_texel_count);
}

}  // namespace
}  // namespace si
