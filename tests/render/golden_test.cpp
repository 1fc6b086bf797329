// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Golden images: one character, a crowd with every LOD, variation and tint, a crossfade.
#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

TEST_P(RenderTest, GoldenSingleCharacter) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  InstanceDesc d;
  d.clip = uint32_t(palette().findClip("walk"));
  d.time_seconds = 0.3;
  d.speed = 0.0f;
  d.color = glm::u8vec4(200, 40, 40, 255);
  d.variation_mask = 0xF;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.update(0.0, closeCamera()).isOk());
  expectGolden("single_walk", draw(r, crowd, closeCamera(), 0));
}

TEST_P(RenderTest, GoldenCrowdWithEveryLodVariationAndTint) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  for (int l = 0; l < 3; ++l) EXPECT_GT(crowd.stats().per_lod[l], 0u) << "LOD " << l;
  expectGolden("crowd_lods", draw(r, crowd, lodCamera(), 0));
}

TEST_P(RenderTest, GoldenCrossfadeMidpoint) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  InstanceDesc d;
  d.clip = uint32_t(palette().findClip("idle"));
  d.color = glm::u8vec4(40, 120, 220, 255);
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.crossfade(h, uint32_t(palette().findClip("wave")), 1.0, 0.5).isOk());
  ASSERT_TRUE(crowd.update(0.5, closeCamera()).isOk());  // Half way through the blend.
  float weight;
  std::memcpy(&weight, &crowd.records()[0].blend[2], 4);
  ASSERT_NEAR(weight, 0.5f, 1e-6f);
  expectGolden("crossfade_mid", draw(r, crowd, closeCamera(), 0));
}

INSTANTIATE_TEST_SUITE_P(Backends, RenderTest, test::allBackends(), test::backendTestName);

}  // namespace
}  // namespace si
