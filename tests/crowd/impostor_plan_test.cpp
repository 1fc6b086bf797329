// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The impostor atlas's plan without a GPU (src/crowd/impostor_plan.h): how many capture texels
// per atlas texel it takes (ImpostorDesc::capture_supersample), what the capture costs, and what
// it refuses or falls back from past a side limit, the byte budget or the back-end's resolve.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

#include "crowd/impostor_plan.h"

namespace si {
namespace {

// Two clips of 20 baked frames in a box 2 units tall.
BakedPalette twoClips() {
  BakedPalette p;
  for (uint32_t c = 0; c < 2; ++c) {
    BakedClip clip;
    clip.frame_count = 20;
    clip.frame_interval_seconds = 1.0 / 30.0;
    clip.first_texel = c * 20 * 66;
    clip.bounds = Aabb{{-0.5f, 0.0f, -0.3f}, {0.5f, 2.0f, 0.3f}};
    p.clips.push_back(clip);
  }
  return p;
}

// Plans `desc` under one side limit `side` (texels) and a back-end resolving up to `most`.
Status plan(const ImpostorDesc& desc, uint32_t side, uint32_t most, detail::ImpostorPlan* out) {
  const detail::ImpostorSide sides[] = {{side, "SIDE_LIMIT"}};
  return detail::planImpostor(twoClips(), 4, desc, Span<const detail::ImpostorSide>(sides, 1), most,
                              "test", out);
}

TEST(ImpostorPlan, TheCaptureIsSupersampledWhereItFits) {
  ImpostorDesc desc;  // 48 views x 16 frames of 32 texels: 28 x 28 cells, 896 texels a side.
  detail::ImpostorPlan p;
  ASSERT_TRUE(plan(desc, 16384, 4, &p).isOk());
  const uint64_t texels = uint64_t(p.info.width) * p.info.height;
  EXPECT_EQ(p.info.capture_supersample, 2u);
  EXPECT_EQ(p.info.capture_bytes, texels * 4 * 16);  // 2 x 2: a depth and three layers.
  // A back-end that resolves nothing captures a texel each: its depth alone.
  ASSERT_TRUE(plan(desc, 16384, 1, &p).isOk());
  EXPECT_EQ(p.info.capture_supersample, 1u);
  EXPECT_EQ(p.info.capture_bytes, texels * 4);
  desc.capture_supersample = 2;
  Status s = plan(desc, 16384, 1, &p);
  EXPECT_EQ(s.code(), StatusCode::kUnsupported) << s.toString();
  // 4 where asked for; other values refused.
  desc.capture_supersample = 4;
  ASSERT_TRUE(plan(desc, 16384, 4, &p).isOk());
  EXPECT_EQ(p.info.capture_bytes, texels * 16 * 16);
  for (uint32_t bad : {3u, 5u, 8u}) {
    desc.capture_supersample = bad;
    s = plan(desc, 16384, 4, &p);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(s.message().find("capture_supersample"), std::string::npos) << s.message();
  }
}

// Each mip level halves every cell: a cell's side is a power of two (one of 48 texels would
// straddle its neighbours from level 5 on), refused by name otherwise.
TEST(ImpostorPlan, CellsArePowersOfTwo) {
  ImpostorDesc desc;
  detail::ImpostorPlan p;
  for (uint32_t cell : {1u, 2u, 16u, 64u, 256u}) {
    desc.cell_pixels = cell;
    ASSERT_TRUE(plan(desc, 1u << 20, 4, &p).isOk()) << cell;
    EXPECT_EQ(p.cell, cell);
    EXPECT_EQ(p.info.cell_pixels, cell);
    EXPECT_EQ(p.info.width % cell, 0u);
  }
  desc.cell_pixels = 0;  // The default.
  ASSERT_TRUE(plan(desc, 16384, 4, &p).isOk());
  EXPECT_EQ(p.cell, 32u);
  EXPECT_EQ(p.info.cell_pixels, 32u);
  for (uint32_t cell : {3u, 48u, 100u, 0x80000001u}) {
    desc.cell_pixels = cell;
    const Status s = plan(desc, 1u << 20, 4, &p);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << cell;
    EXPECT_NE(s.message().find("cell_pixels"), std::string::npos) << s.message();
  }
}

// The sampler's LOD bias: within [-2, 2] mip levels (what every GL 4 and Vulkan device takes),
// refused by name otherwise.
TEST(ImpostorPlan, TheLodBiasIsWithinTwoLevels) {
  ImpostorDesc desc;
  detail::ImpostorPlan p;
  for (float bias : {-2.0f, -0.5f, 0.0f, 1.0f, 2.0f}) {
    desc.lod_bias = bias;
    EXPECT_TRUE(plan(desc, 16384, 4, &p).isOk()) << bias;
  }
  for (float bias : {-2.5f, 2.01f, std::numeric_limits<float>::quiet_NaN(),
                     std::numeric_limits<float>::infinity()}) {
    desc.lod_bias = bias;
    const Status s = plan(desc, 16384, 4, &p);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << bias;
    EXPECT_NE(s.message().find("lod_bias"), std::string::npos) << s.message();
  }
}

TEST(ImpostorPlan, TheDefaultFallsBackWhereTwoWouldPassALimit) {
  ImpostorDesc desc;
  detail::ImpostorPlan p;
  ASSERT_TRUE(plan(desc, 16384, 4, &p).isOk());
  const uint32_t side = std::max(p.info.width, p.info.height);
  const uint64_t atlas = p.info.bytes, texels = uint64_t(p.info.width) * p.info.height;
  // A side limit the atlas fits but not twice its side.
  ASSERT_TRUE(plan(desc, 2 * side - 1, 4, &p).isOk());
  EXPECT_EQ(p.info.capture_supersample, 1u);
  desc.capture_supersample = 2;
  Status s = plan(desc, 2 * side - 1, 4, &p);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("SIDE_LIMIT"), std::string::npos) << s.message();
  EXPECT_EQ(p.info.capture_supersample, 2u);  // The plan refused is reported.
  // A budget that holds the capture a texel each but not 2 x 2.
  desc = ImpostorDesc();
  desc.max_bytes = atlas + texels * 4;
  ASSERT_TRUE(plan(desc, 16384, 4, &p).isOk());
  EXPECT_EQ(p.info.capture_supersample, 1u);
  desc.capture_supersample = 2;
  s = plan(desc, 16384, 4, &p);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("max_bytes"), std::string::npos) << s.message();
  // Exactly 2 x 2's bytes: the default takes it.
  desc = ImpostorDesc();
  desc.max_bytes = atlas + texels * 64;
  ASSERT_TRUE(plan(desc, 16384, 4, &p).isOk());
  EXPECT_EQ(p.info.capture_supersample, 2u);
}

}  // namespace
}  // namespace si
