// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A mesh's optional vertex words on the GPU: the generated patch's COLOR_0 and TEXCOORD_1
// (tests/gltf/pbr_asset.h) reach the surface as the file gives them, and the built-in material
// multiplies the base colour by the vertex colour (on the ES profile too).
#include <algorithm>
#include <string>
#include <vector>

#include "render/pbr_material_fixture.h"

namespace si {
namespace {

using namespace test;

class VertexWordsTest : public PbrMaterialTest {
 protected:
  // The patch with the built-in material on the instanced path, without and with COLOR_0
  // (RGB u8: red u, green 1 - v, blue 0.5), into the bound framebuffer: the painted one is
  // nowhere brighter, and the red it keeps grows from the left of the patch to the right.
  void expectVertexColoursToDarkenTheBuiltInLook() {
    std::vector<uint8_t> images[2];
    for (int painted = 0; painted < 2; ++painted) {
      PbrAssetDesc d;
      d.colors = painted ? 3 : 0;
      load(d);
      glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      Renderer r;
      drawPatch(PathKind::kInstanced, nullptr, &r);
      if (HasFatalFailure()) return;
      ASSERT_TRUE(context_->readPixels(&images[painted]).isOk());
    }
    const std::vector<uint8_t>&plain = images[0], &painted = images[1];
    size_t covered = 0, brighter = 0;
    uint32_t left = kSize, right = 0;
    for (size_t p = 0; p < plain.size(); p += 4) {
      if (plain[p] + plain[p + 1] + plain[p + 2] == 0) continue;
      ++covered;
      for (int c = 0; c < 3; ++c) brighter += painted[p + c] > plain[p + c] + 2;
      const uint32_t x = uint32_t(p / 4 % kSize);
      left = std::min(left, x);
      right = std::max(right, x);
    }
    ASSERT_GT(covered, size_t(kSize) * kSize / 20);
    EXPECT_EQ(brighter, 0u);
    // The red kept, painted over plain, in the left and the right third of the patch.
    double kept[2] = {0.0, 0.0};
    size_t counted[2] = {0, 0};
    const uint32_t third = (right - left) / 3;
    for (size_t p = 0; p < plain.size(); p += 4) {
      if (plain[p] < 20) continue;
      const uint32_t x = uint32_t(p / 4 % kSize);
      const int side = x < left + third ? 0 : x > right - third ? 1 : -1;
      if (side < 0) continue;
      kept[side] += double(painted[p]) / plain[p];
      ++counted[side];
    }
    ASSERT_GT(counted[0], 100u);
    ASSERT_GT(counted[1], 100u);
    EXPECT_GT(kept[1] / counted[1], kept[0] / counted[0] + 0.2)
        << "left " << kept[0] / counted[0] << ", right " << kept[1] / counted[1];
  }
};

// The file's COLOR_0 and TEXCOORD_1 reach the surface as it gives them: on the patch COLOR_0
// is (x + 0.5, y, 0.5) = (u, 1 - v, 0.5) in 8 bits and TEXCOORD_1 (2 y, x + 0.5) = (2 (1 - v),
// u), linear in the patch, so every covered pixel's interpolated values follow from its uv0
// (within the 8-bit colour's and the half float's rounding), on the instanced and the
// GPU-driven pre-skinned path (the vertex attributes and the source words).
TEST_P(VertexWordsTest, VertexColoursAndSecondTextureCoordinatesReachTheSurface) {
  constexpr const char* kVertexProbe = R"(
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_uv;
void siMaterial(SiSurface s) {
  o_color = s.color;
  o_uv = vec4(s.uv0, s.uv1);
})";
  PbrAssetDesc d;
  d.colors = 3;
  d.texcoords1 = true;
  load(d);
  for (PathKind kind : {PathKind::kInstanced, PathKind::kGpuDrivenCompute}) {
    SCOPED_TRACE(pathKindName(kind));
    TwoTargets targets(kSize, GL_RGBA32F);
    targets.clear(glm::vec4(0.0f));
    Renderer r;
    drawPatch(kind, kVertexProbe, &r);
    if (HasFatalFailure()) return;
    const std::vector<glm::vec4> colors = targets.readFloat(0), uvs = targets.readFloat(1);
    size_t covered = 0;
    float worst_color = 0.0f, worst_uv1 = 0.0f;
    for (size_t p = 0; p < colors.size(); ++p) {
      if (colors[p].a == 0.0f) continue;  // Background (the colour's alpha is 1).
      ++covered;
      const glm::vec2 uv(uvs[p]);
      const glm::vec4 expected(uv.x, 1.0f - uv.y, 128.0f / 255.0f, 1.0f);
      const glm::vec4 e = glm::abs(colors[p] - expected);
      worst_color = std::max({worst_color, e.x, e.y, e.z, e.w});
      const glm::vec2 f =
          glm::abs(glm::vec2(uvs[p].z, uvs[p].w) - glm::vec2(2.0f * (1.0f - uv.y), uv.x));
      worst_uv1 = std::max({worst_uv1, f.x, f.y});
    }
    EXPECT_GT(covered, size_t(kSize) * kSize / 20);
    EXPECT_LE(worst_color, 0.6f / 255.0f) << "8 bits a channel at the vertices";
    EXPECT_LE(worst_uv1, 2.0f / 1024.0f) << "half floats up to 2";
  }
}

// The built-in material multiplies the base colour by the vertex colour (glTF): the painted
// patch is nowhere brighter than the plain one, and its red, which grows with u, darkens the
// left of the patch more than the right. On the ES profile too (EsPbrMaterialTest).
TEST_P(VertexWordsTest, TheBuiltInMaterialMultipliesTheBaseColourByTheVertexColour) {
  expectVertexColoursToDarkenTheBuiltInLook();
}

INSTANTIATE_TEST_SUITE_P(Backends, VertexWordsTest, test::allBackends(), test::backendTestName);

class EsVertexWordsTest : public VertexWordsTest {
 protected:
  bool es() const override { return true; }
};

TEST_P(EsVertexWordsTest, TheBuiltInMaterialMultipliesTheBaseColourByTheVertexColour) {
  expectVertexColoursToDarkenTheBuiltInLook();
}

INSTANTIATE_TEST_SUITE_P(Backends, EsVertexWordsTest, test::esBackends(), test::backendTestName);

}  // namespace
}  // namespace si
