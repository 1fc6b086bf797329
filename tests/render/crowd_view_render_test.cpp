// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Views drawn (si::CrowdView): a light view of a crowd advanced once and selected for two
// cameras draws, depth-only, exactly the depth image of a crowd with only that view, and the
// main view's image is unchanged by drawing the light view before it, on the instanced,
// compute, traditional and CPU-skinning paths. The light view sees characters the main camera
// culls (behind it), at its own coarser LODs.
#include <glad/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include "render/render_fixture.h"
#include "render/view_scenes.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/crowd_view.h"
#include "si/gl/motion_target.h"

namespace si {
namespace {

using namespace test;

// A sun-like orthographic camera up and to the side of the near rows, looking down at them.
Camera lightCamera() {
  return test::lightCamera(glm::dvec3(0.0, 0.0, 2.0), glm::dvec3(30.0, 50.0, 25.0), 16.0f);
}

// The LOD scene plus a row behind the main camera (which it culls and the light sees).
void populate(CrowdManager* crowd, std::vector<InstanceHandle>* behind) {
  populateLodCrowd(crowd);
  addRowBehind(crowd, behind);
}

bool drawn(const CrowdView& view, InstanceHandle h) {
  for (InstanceHandle v : view.visibleHandles())
    if (v == h) return true;
  return false;
}

enum class ViewPath { kInstanced, kCompute, kTraditional, kCpuSkinned };
const char* pathName(ViewPath p) {
  return p == ViewPath::kInstanced ? "instanced" : p == ViewPath::kCompute ? "compute"
         : p == ViewPath::kTraditional ? "traditional" : "cpu-skinned";
}

Status drawView(Renderer& r, const InstanceBatcher& batcher, const CrowdView& view,
                const Camera& camera, ViewPath path, DrawMode mode) {
  DrawStats stats;
  switch (path) {
    case ViewPath::kInstanced:
      return r.drawCrowd(CharacterId{}, view, batcher, camera, &stats, mode);
    case ViewPath::kCompute:
      return r.drawCrowd(CharacterId{}, view, batcher, camera, &stats,
                         mode == DrawMode::kDepthOnly ? mode : DrawMode::kComputeSkinned);
    case ViewPath::kTraditional: return r.drawTraditional(CharacterId{}, view, camera, &stats);
    case ViewPath::kCpuSkinned: return r.drawCpuSkinned(CharacterId{}, view, camera, &stats);
  }
  return Status::ok();
}

TEST_P(RenderTest, EachViewDrawsWhatACrowdWithOnlyThatViewDraws) {
  Renderer r;
  makeRenderer(&r);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  // `both` is drawn from two views; `main_only` by update() alone; `light_only` by its one view.
  CrowdManager both, main_only, light_only;
  std::vector<InstanceHandle> behind;
  for (CrowdManager* c : {&both, &main_only, &light_only}) {
    makeCrowd(c);
    behind.clear();
    populate(c, &behind);
  }
  CrowdViewDesc shadow;
  shadow.lod_bias = 1;
  shadow.max_distance_radii = -1.0f;
  CrowdView main_view, light_view, light_alone;
  ASSERT_TRUE(main_view.init(both).isOk());
  ASSERT_TRUE(light_view.init(both, shadow).isOk());
  ASSERT_TRUE(light_alone.init(light_only, shadow).isOk());
  const Camera main_camera = closeCamera(), light = lightCamera();
  for (int frame = 0; frame < 2; ++frame) {
    ASSERT_TRUE(both.advance(0.2).isOk());
    ASSERT_TRUE(light_view.select(light).isOk());
    ASSERT_TRUE(main_view.select(main_camera).isOk());
    ASSERT_TRUE(main_only.update(0.2, main_camera).isOk());
    ASSERT_TRUE(light_only.advance(0.2).isOk());
    ASSERT_TRUE(light_alone.select(light).isOk());
  }
  // The light sees the row behind the main camera, which the main view culls.
  for (InstanceHandle h : behind) {
    EXPECT_TRUE(drawn(light_view, h));
    EXPECT_FALSE(drawn(main_view, h));
  }
  EXPECT_EQ(light_view.stats().per_lod[0], 0u);  // lod_bias 1.
  for (ViewPath path : {ViewPath::kInstanced, ViewPath::kCompute, ViewPath::kTraditional,
                        ViewPath::kCpuSkinned}) {
    SCOPED_TRACE(pathName(path));
    // The reference images: each crowd with one view, drawn alone.
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    ASSERT_TRUE(drawView(r, batcher, light_alone, light, path, DrawMode::kDepthOnly).isOk());
    const std::vector<float> light_reference = readDepth();
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    ASSERT_TRUE(drawView(r, batcher, main_only.view(), main_camera, path, DrawMode::kDefault).isOk());
    std::vector<uint8_t> main_reference;
    ASSERT_TRUE(context_->readPixels(&main_reference).isOk());
    // The frame: the light view's depth first (a shadow map), then the main view.
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    ASSERT_TRUE(drawView(r, batcher, light_view, light, path, DrawMode::kDepthOnly).isOk());
    const std::vector<float> light_depth = readDepth();
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    ASSERT_TRUE(drawView(r, batcher, main_view, main_camera, path, DrawMode::kDefault).isOk());
    std::vector<uint8_t> main_image;
    ASSERT_TRUE(context_->readPixels(&main_image).isOk());
    size_t covered = 0, differ = 0;
    for (size_t p = 0; p < light_depth.size(); ++p) {
      covered += light_depth[p] < 1.0f;
      differ += light_depth[p] != light_reference[p];
    }
    EXPECT_GT(covered, 200u) << "the light view draws characters";
    EXPECT_EQ(differ, 0u) << "of " << covered << " covered depth pixels";
    EXPECT_EQ(compare(main_image, main_reference, nullptr).max_channel, 0);
  }
}

// Motion vectors are each view's own: a second camera's view of a crowd that a main view also
// selects draws the motion image of a crowd with only that view (three frames, both cameras
// moving, crossfades and a speed change between them), on both skinning paths.
TEST_P(RenderTest, EachViewDrawsItsOwnMotionVectors) {
  MotionTarget target;
  ASSERT_TRUE(target.create(kSize, kSize).isOk());
  target.bind();
  Renderer r;
  RendererDesc rd;
  rd.motion_vectors = true;
  rd.skinning_path = SkinningPath::kVertexShader;
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  CrowdManager both, alone;
  std::vector<InstanceHandle> handles[2];
  for (int c = 0; c < 2; ++c) {
    CrowdManager& crowd = c == 0 ? both : alone;
    makeCrowd(&crowd);
    populate(&crowd, &handles[c]);
  }
  CrowdViewDesc with_motion;
  with_motion.previous_records = true;
  CrowdView main_view, second, second_alone;
  ASSERT_TRUE(main_view.init(both, with_motion).isOk());
  ASSERT_TRUE(second.init(both, with_motion).isOk());
  ASSERT_TRUE(second_alone.init(alone, with_motion).isOk());
  const auto main_camera = [](int f) {
    return Camera::lookAt({0.4 * f, 1.5, 4.0 - 0.3 * f}, {0.0, 0.8, -4.0}, glm::vec3(0, 1, 0),
                          0.9f, 1.0f, 0.1f, 200.0f);
  };
  const auto second_camera = [](int f) {  // A second player, behind the first row.
    return Camera::lookAt({-2.0 + 0.5 * f, 1.7, -8.0}, {0.0, 0.9, 9.0}, glm::vec3(0, 1, 0),
                          0.9f, 1.0f, 0.1f, 200.0f);
  };
  size_t moving = 0;
  for (int f = 0; f < 3; ++f) {
    for (int c = 0; c < 2; ++c) {
      CrowdManager& crowd = c == 0 ? both : alone;
      if (f == 1) {
        ASSERT_TRUE(crowd.crossfade(handles[c][0], 1, 0.3).isOk());
        ASSERT_TRUE(crowd.play(handles[c][1], 0, 0.2, 2.5f).isOk());
      }
      ASSERT_TRUE(crowd.advance(1.0 / 30.0).isOk());
    }
    ASSERT_TRUE(main_view.select(main_camera(f)).isOk());
    ASSERT_TRUE(second.select(second_camera(f)).isOk());
    ASSERT_TRUE(second_alone.select(second_camera(f)).isOk());
    if (f == 0) continue;  // From the second frame on, there is a previous one.
    for (DrawMode mode : {DrawMode::kSkinned, DrawMode::kComputeSkinned}) {
      DrawStats stats;
      target.clear(glm::vec4(0.0f));
      ASSERT_TRUE(
          r.drawCrowd(si::CharacterId{}, second_alone, batcher, second_camera(f), &stats, mode)
              .isOk());
      std::vector<glm::vec2> expected, drawn;
      ASSERT_TRUE(target.readMotion(&expected).isOk());
      target.clear(glm::vec4(0.0f));
      ASSERT_TRUE(
          r.drawCrowd(CharacterId{}, main_view, batcher, main_camera(f), &stats, mode).isOk());
      target.clear(glm::vec4(0.0f));
      ASSERT_TRUE(
          r.drawCrowd(si::CharacterId{}, second, batcher, second_camera(f), &stats, mode).isOk());
      ASSERT_TRUE(target.readMotion(&drawn).isOk());
      ASSERT_EQ(drawn.size(), expected.size());
      size_t differ = 0;
      for (size_t p = 0; p < drawn.size(); ++p) {
        differ += drawn[p] != expected[p];
        moving += glm::length(expected[p]) > 1e-3f;
      }
      EXPECT_EQ(differ, 0u) << "frame " << f << (mode == DrawMode::kSkinned ? " vertex" : " compute");
    }
  }
  EXPECT_GT(moving, 100u) << "the second view's characters move on screen";
  target.restore();
  target.release();
}

// Drawing a view that is not attached is refused by name.
TEST_P(RenderTest, ADetachedViewIsRefused) {
  Renderer r;
  makeRenderer(&r);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  CrowdView view;
  DrawStats stats;
  const Status s = r.drawCrowd(CharacterId{}, view, batcher, closeCamera(), &stats);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("not attached"), std::string::npos) << s.message();
  EXPECT_EQ(r.drawTraditional(CharacterId{}, view, closeCamera(), &stats).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(r.drawCpuSkinned(CharacterId{}, view, closeCamera(), &stats).code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace si
