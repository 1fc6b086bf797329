// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Y-flipped targets (render textures as OGRE and others draw them: the projection's y negated):
// every path, impostors and occlusion culling included, draws the standard image upside down,
// with the same faces culled (Camera::flipsWinding: the draws take clockwise front faces).
#include <cstring>

#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

class FlippedTargetTest : public RenderTest {
 protected:
  // Clears and draws `crowd` with `camera` on `kind`; the image.
  std::vector<uint8_t> drawKind(Renderer& r, PathKind kind, const CrowdManager& crowd,
                                const Camera& camera) {
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    const Status s = drawOnPath(r, kind, crowd, camera, nullptr);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  }
};

TEST_P(FlippedTargetTest, EveryPathDrawsTheStandardImageUpsideDown) {
  EXPECT_FALSE(lodCamera().flipsWinding());
  EXPECT_TRUE(yFlipped(lodCamera()).flipsWinding());
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  addFadingCharacter(&crowd);
  ASSERT_TRUE(crowd.update(0.3, lodCamera()).isOk());
  Renderer r;
  makeRenderer(&r);
  const std::vector<uint8_t> expected =
      flipped(drawKind(r, PathKind::kInstanced, crowd, lodCamera()));
  for (PathKind kind : kEveryPath) {
    SCOPED_TRACE(pathKindName(kind));
    const Diff diff = compare(drawKind(r, kind, crowd, yFlipped(lodCamera())), expected, nullptr);
    EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
  }
}

TEST_P(FlippedTargetTest, ImpostorsAndOcclusionCullingDrawTheStandardImageUpsideDown) {
  // Impostors: rows of 16 far characters drawn as quads, on the instanced and GPU-driven paths.
  Renderer r;
  RendererDesc vs;
  vs.skinning_path = SkinningPath::kVertexShader;
  ASSERT_TRUE(r.init(info_, vs).isOk());
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(impostorCharacter(), palette(), &id).isOk());
  ImpostorDesc small;
  small.azimuths = 8;
  small.frames_per_clip = 4;
  ASSERT_TRUE(r.buildImpostor(id, small).isOk());
  CrowdManager far;
  impostorRowsCrowd(3.0, 30.0, 20.0, &far);
  for (PathKind kind : {PathKind::kInstanced, PathKind::kGpuDriven}) {
    SCOPED_TRACE(pathKindName(kind));
    const std::vector<uint8_t> expected = flipped(drawKind(r, kind, far, lodCamera()));
    const Diff diff = compare(drawKind(r, kind, far, yFlipped(lodCamera())), expected, nullptr);
    EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
  }
  // Occlusion culling: the wall scene, three frames each (the last culls what the wall hides).
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.gpu_occlusion_culling = true;
  rd.measure_gpu_time = true;
  Renderer occluding;
  makeRenderer(&occluding, 0, PaletteFormat::kMatrix3x4F32, &rd);
  CrowdManager wall;
  makeCrowd(&wall);
  populateWallCrowd(&wall);
  std::vector<uint8_t> images[2];
  for (int flip = 0; flip < 2; ++flip) {
    const Camera camera = flip ? yFlipped(wallCamera()) : wallCamera();
    for (int frame = 0; frame < 3; ++frame)
      images[flip] = drawKind(occluding, PathKind::kGpuDriven, wall, camera);
  }
  const Diff diff = compare(images[1], flipped(images[0]), nullptr);
  EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
}

INSTANTIATE_TEST_SUITE_P(Backends, FlippedTargetTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
