// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Golden images: one character, a crowd with every LOD, variation and tint, a crossfade.
#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

TEST_P(RenderTest, GoldenSingleCharacter) {
  goldenSingleCharacter();
}
TEST_P(RenderTest, GoldenCrowdWithEveryLodVariationAndTint) {
  goldenCrowdLods();
}
TEST_P(RenderTest, GoldenCrossfadeMidpoint) {
  goldenCrossfadeMidpoint();
}

INSTANTIATE_TEST_SUITE_P(Backends, RenderTest, test::allBackends(), test::backendTestName);

}  // namespace
}  // namespace si
