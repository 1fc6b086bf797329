// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The impostor atlas's supersampled capture (ImpostorDesc::capture_supersample): at the atlas's
// own views and frames, an impostor captured 2 x 2 texels per atlas texel changes fewer pixels
// of the character's image than one captured a texel each; what the build reports, and what
// it refuses or falls back from past a limit.
#include <glad/gl.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "render/impostor_fixture.h"
#include "si/gl/image_lod_error.h"

namespace si {
namespace {

using namespace test;

// The impostor's mean differing pixels against LOD 0 at 8 pixels tall, 4 x 4 supersampled, at
// views and frames its atlas captured (smallImpostor(): 8 azimuths at 0 and 30 degrees, 4
// frames a clip, which 3 poses a clip at thirds of its duration fall on).
double errorAtCapturedViews(const GlInfo& info, uint32_t capture_supersample) {
  ImpostorDesc id = smallImpostor();
  id.capture_supersample = capture_supersample;
  ImageLodErrorDesc d;
  d.heights_pixels = {8};
  d.azimuths = 8;
  d.elevations_degrees = {0.0f, 30.0f};
  d.poses_per_clip = 3;
  d.max_poses = 6;
  d.impostor = &id;
  ImageLodErrorReport report;
  const Status s = measureImageLodErrors(info, impostorCharacter(), palette(), d, &report);
  EXPECT_TRUE(s.isOk()) << s.toString();
  return s.isOk() ? report.levels.back().mean_differing_pixels[0] : 0.0;
}

TEST_P(RenderTest, ASupersampledCaptureChangesFewerPixelsAtTheCapturedViews) {
  const double aliased = errorAtCapturedViews(info_, 1);
  const double supersampled = errorAtCapturedViews(info_, 2);
  std::printf("[ capture ] differing pixels at 8 px: %.2f captured 1 x 1, %.2f captured 2 x 2\n",
              aliased, supersampled);
  EXPECT_GT(aliased, 0.0);
  EXPECT_LT(supersampled, 0.75 * aliased);
}

TEST_P(RenderTest, TheCaptureIsSupersampledWithinItsLimits) {
  Renderer r;
  ASSERT_TRUE(r.init(info_, {}).isOk());
  CharacterId cid;
  ASSERT_TRUE(r.addCharacter(impostorCharacter(), palette(), &cid).isOk());
  // The default: 2 x 2, the capture's depth and its own three layers, 4 bytes a texel each.
  ImpostorInfo built;
  ASSERT_TRUE(r.buildImpostor(cid, smallImpostor(), &built).isOk());
  const uint64_t texels = uint64_t(built.width) * built.height;
  EXPECT_EQ(built.capture_supersample, 2u);
  EXPECT_EQ(built.capture_bytes, texels * 4 * 16);
  EXPECT_TRUE(built.uniform_surface);  // Measured on the capture's whole texels.
  // 1: drawn into the atlas, the depth alone; 4: 4 x 4.
  ImpostorDesc d = smallImpostor();
  for (uint32_t ss : {1u, 4u}) {
    d.capture_supersample = ss;
    ImpostorInfo info;
    ASSERT_TRUE(r.buildImpostor(cid, d, &info).isOk());
    EXPECT_EQ(info.capture_supersample, ss);
    EXPECT_EQ(info.capture_bytes, texels * ss * ss * (ss > 1 ? 16 : 4));
    EXPECT_EQ(info.bytes, built.bytes);  // The atlas is as large.
  }
  for (uint32_t ss : {3u, 8u}) {
    d.capture_supersample = ss;
    const Status s = r.buildImpostor(cid, d);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(s.message().find("capture_supersample"), std::string::npos) << s.message();
  }
  // A budget that holds the capture a texel each but not 2 x 2: the default falls back to 1;
  // asked for 2, refused before allocating.
  d = smallImpostor();
  d.max_bytes = built.bytes + texels * 4;
  ImpostorInfo fallback;
  ASSERT_TRUE(r.buildImpostor(cid, d, &fallback).isOk());
  EXPECT_EQ(fallback.capture_supersample, 1u);
  d.capture_supersample = 2;
  Status s = r.buildImpostor(cid, d);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("max_bytes"), std::string::npos) << s.message();
  r.shutdown();
  // A viewport limit (lowered, as a smaller GPU's) the atlas fits but not twice its height:
  // the default falls back to 1; asked for 2, refused by name.
  GlInfo small = info_;
  small.max_viewport_height = 2 * built.height - 1;
  Renderer lowered;
  ASSERT_TRUE(lowered.init(small, {}).isOk());
  CharacterId lid;
  ASSERT_TRUE(lowered.addCharacter(impostorCharacter(), palette(), &lid).isOk());
  ASSERT_TRUE(lowered.buildImpostor(lid, smallImpostor(), &fallback).isOk());
  EXPECT_EQ(fallback.capture_supersample, 1u);
  d = smallImpostor();
  d.capture_supersample = 2;
  s = lowered.buildImpostor(lid, d);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("GL_MAX_VIEWPORT_DIMS"), std::string::npos) << s.message();
  lowered.shutdown();
}

}  // namespace
}  // namespace si
