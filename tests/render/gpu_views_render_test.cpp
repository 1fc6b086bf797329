// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Views on the GPU-driven path (Renderer::drawCrowdGpuCulled of a CrowdView): one crowd drawn
// from a main view and a shadow view (depth only, coarser LODs, no far line) gives each view
// exactly what a crowd with only that view draws (depth image, colour image, GPU selection and
// counts), frame after frame, in either order, with the vertex-shader path and with
// pre-skinning and two-phase occlusion culling. Motion vectors are each view's own. Each crowd
// is drawn by its own character of one renderer (a character keeps the GPU state of one crowd).
#include <glad/gl.h>

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>

#include "render/render_fixture.h"
#include "render/view_scenes.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/crowd_view.h"
#include "si/gl/motion_target.h"

namespace si {
namespace {

using namespace test;

// A sun-like orthographic camera up and to the side of the near rows, looking down at them
// (near enough that its distance LOD there is 0).
Camera lightCamera() {
  return test::lightCamera(glm::dvec3(0.0, 0.0, -6.0), glm::dvec3(6.0, 10.0, 5.0), 24.0f);
}

// The main camera walks forward frame by frame: instances cross LOD lines and sit inside the
// hysteresis bands, where a view's own history decides its LOD.
Camera mainCamera(int frame) {
  return Camera::lookAt({0.3 * frame, 3.0, 6.0 - 2.5 * frame}, {0.0, 0.0, -40.0},
                        glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f, 500.0f);
}

// The LOD scene, a row behind the main camera (which it culls and the light sees) and a
// crossfading character.
void populate(CrowdManager* crowd) {
  populateLodCrowd(crowd);
  addFadingCharacter(crowd);
  addRowBehind(crowd, nullptr);
}

// One view's draw: the image (colour, or depth for a depth-only draw), the counts and the
// GPU's selection, sorted.
struct ViewDraw {
  std::vector<uint8_t> colour;
  std::vector<float> depth;
  DrawStats stats;
  std::vector<glm::uvec2> selection;
};

class GpuViews : public RenderTest {
 protected:
  ViewDraw drawView(Renderer& r, CharacterId id, const CrowdView& view, const Camera& camera,
                    DrawMode mode) {
    ViewDraw out;
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    const Status s = r.drawCrowdGpuCulled(id, view, camera, &out.stats, mode);
    EXPECT_TRUE(s.isOk()) << s.toString();
    if (mode == DrawMode::kDepthOnly) out.depth = readDepth();
    else EXPECT_TRUE(context_->readPixels(&out.colour).isOk());
    EXPECT_TRUE(r.readGpuSelection(id, &out.selection).isOk());
    std::sort(out.selection.begin(), out.selection.end(),
              [](glm::uvec2 a, glm::uvec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    return out;
  }
};

void expectSame(const ViewDraw& a, const ViewDraw& reference) {
  EXPECT_TRUE(a.colour == reference.colour);
  EXPECT_TRUE(a.depth == reference.depth);
  EXPECT_EQ(a.stats.gpu_visible, reference.stats.gpu_visible);
  EXPECT_EQ(a.stats.instances, reference.stats.instances);
  EXPECT_EQ(a.stats.triangles, reference.stats.triangles);
  EXPECT_EQ(a.stats.skinned_vertices, reference.stats.skinned_vertices);
  EXPECT_TRUE(a.selection == reference.selection) << a.selection.size() << " selected, "
                                                  << reference.selection.size() << " expected";
}

TEST_P(GpuViews, EachViewDrawsWhatACrowdWithOnlyThatViewDraws) {
  // The vertex-shader path without occlusion culling; pre-skinning with it.
  for (int variant = 0; variant < 2; ++variant) {
    SCOPED_TRACE(variant == 0 ? "vertex shader" : "pre-skinning, occlusion culling");
    Renderer r;
    RendererDesc rd;
    rd.skinning_path = variant == 0 ? SkinningPath::kVertexShader : SkinningPath::kCompute;
    rd.gpu_occlusion_culling = variant == 1;
    rd.measure_gpu_time = true;  // Reads back the counts.
    makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
    // Character 0 draws `both` from two views; 1 `main_only` (its own view); 2 `light_only`.
    CharacterId ids[3];
    for (int c = 1; c < 3; ++c) ASSERT_TRUE(r.addCharacter(character(), palette(), &ids[c]).isOk());
    CrowdManager both, main_only, light_only;
    for (CrowdManager* c : {&both, &main_only, &light_only}) {
      makeCrowd(c);
      populate(c);
    }
    CrowdViewDesc shadow;
    shadow.lod_bias = 1;
    shadow.max_distance_radii = -1.0f;
    CrowdView light_view, light_alone;
    ASSERT_TRUE(light_view.init(both, shadow).isOk());
    ASSERT_TRUE(light_alone.init(light_only, shadow).isOk());
    const Camera light = lightCamera();
    for (int frame = 0; frame < 4; ++frame) {
      SCOPED_TRACE(frame);
      for (CrowdManager* c : {&both, &main_only, &light_only}) ASSERT_TRUE(c->advance(0.2).isOk());
      const Camera main_camera = mainCamera(frame);
      const ViewDraw light_reference =
          drawView(r, ids[2], light_alone, light, DrawMode::kDepthOnly);
      const ViewDraw main_reference =
          drawView(r, ids[1], main_only.view(), main_camera, DrawMode::kDefault);
      // Views in either order: the light first at even frames, the main view first at odd.
      ViewDraw light_drawn, main_drawn;
      if (frame % 2 == 0) light_drawn = drawView(r, ids[0], light_view, light, DrawMode::kDepthOnly);
      main_drawn = drawView(r, ids[0], both.view(), main_camera, DrawMode::kDefault);
      if (frame % 2 == 1) light_drawn = drawView(r, ids[0], light_view, light, DrawMode::kDepthOnly);
      {
        SCOPED_TRACE("light view");
        expectSame(light_drawn, light_reference);
      }
      {
        SCOPED_TRACE("main view");
        expectSame(main_drawn, main_reference);
      }
      // The light sees the row behind the main camera (dense indices 25 to 28), which the main
      // view culls, only at its coarser LODs.
      const auto selects = [](const ViewDraw& d, uint32_t index) {
        for (const glm::uvec2& s : d.selection)
          if (s.x == index) return true;
        return false;
      };
      // (With occlusion culling the selection read back is the second phase's only.)
      for (uint32_t behind = 25; behind < 29 && variant == 0; ++behind) {
        EXPECT_TRUE(selects(light_drawn, behind)) << behind;
        EXPECT_FALSE(selects(main_drawn, behind)) << behind;
      }
      size_t covered = 0;
      for (float d : light_drawn.depth) covered += d < 1.0f;
      EXPECT_GT(covered, 100u) << "the light view draws characters";
      size_t biased = 0;  // Drawn at LOD 1: at LOD 0 without the bias.
      for (const glm::uvec2& s : light_drawn.selection) {
        EXPECT_GE(s.y, 1u) << "lod_bias 1";
        biased += s.y == 1;
      }
      if (variant == 0) {
        EXPECT_GT(biased, 4u);
      }
      if (variant == 1) {
        EXPECT_GT(main_drawn.stats.skinned_vertices, 0u);  // Pre-skinned.
        EXPECT_GT(light_drawn.stats.skinned_vertices, 0u);
      }
    }
  }
}

// Motion vectors are each view's own on the GPU-driven path: a main view and a second camera's
// view of one crowd each give the motion image of a crowd with only that view (three frames,
// both cameras moving, a crossfade and a speed change), skinned in the vertex shader and
// pre-skinned.
TEST_P(GpuViews, EachViewDrawsItsOwnMotionVectors) {
  MotionTarget target;
  ASSERT_TRUE(target.create(kSize, kSize).isOk());
  target.bind();
  Renderer r;
  RendererDesc rd;
  rd.motion_vectors = true;
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
  // Character 0 draws `both` from two views; 1 and 2 a crowd with only one of them.
  CharacterId ids[3];
  for (int c = 1; c < 3; ++c) ASSERT_TRUE(r.addCharacter(character(), palette(), &ids[c]).isOk());
  CrowdManager crowds[3];
  InstanceHandle first[3], second_handle[3];
  for (int c = 0; c < 3; ++c) {
    makeCrowd(&crowds[c]);
    populateLodCrowd(&crowds[c]);
    InstanceDesc d;
    d.position = glm::dvec3(-1.0, 0.0, 6.0);
    ASSERT_TRUE(crowds[c].add(d, &first[c]).isOk());
    d.position = glm::dvec3(1.5, 0.0, 7.0);
    ASSERT_TRUE(crowds[c].add(d, &second_handle[c]).isOk());
  }
  CrowdView second, second_alone;
  ASSERT_TRUE(second.init(crowds[0]).isOk());
  ASSERT_TRUE(second_alone.init(crowds[2]).isOk());
  const auto main_camera = [](int f) {
    return Camera::lookAt({0.4 * f, 1.5, 4.0 - 0.3 * f}, {0.0, 0.8, -4.0}, glm::vec3(0, 1, 0),
                          0.9f, 1.0f, 0.1f, 200.0f);
  };
  const auto second_camera = [](int f) {  // A second player, looking back at the near rows.
    return Camera::lookAt({-2.0 + 0.5 * f, 1.7, -8.0}, {0.0, 0.9, 9.0}, glm::vec3(0, 1, 0),
                          0.9f, 1.0f, 0.1f, 200.0f);
  };
  const auto motion = [&](CharacterId id, const CrowdView& view, const Camera& camera,
                          DrawMode mode) {
    std::vector<glm::vec2> out;
    DrawStats stats;
    target.clear(glm::vec4(0.0f));
    EXPECT_TRUE(r.drawCrowdGpuCulled(id, view, camera, &stats, mode).isOk());
    EXPECT_TRUE(target.readMotion(&out).isOk());
    return out;
  };
  size_t moving = 0;
  for (int f = 0; f < 3; ++f) {
    for (int c = 0; c < 3; ++c) {
      if (f == 1) {
        ASSERT_TRUE(crowds[c].crossfade(first[c], 1, 0.3).isOk());
        ASSERT_TRUE(crowds[c].play(second_handle[c], 0, 0.2, 2.5f).isOk());
      }
      ASSERT_TRUE(crowds[c].advance(1.0 / 30.0).isOk());
    }
    for (DrawMode mode : {DrawMode::kSkinned, DrawMode::kComputeSkinned}) {
      SCOPED_TRACE(testing::Message() << "frame " << f
                                      << (mode == DrawMode::kSkinned ? " vertex" : " compute"));
      const std::vector<glm::vec2> main_expected =
          motion(ids[1], crowds[1].view(), main_camera(f), mode);
      const std::vector<glm::vec2> second_expected =
          motion(ids[2], second_alone, second_camera(f), mode);
      const std::vector<glm::vec2> main_drawn =
          motion(ids[0], crowds[0].view(), main_camera(f), mode);
      const std::vector<glm::vec2> second_drawn =
          motion(ids[0], second, second_camera(f), mode);
      ASSERT_EQ(main_drawn.size(), main_expected.size());
      ASSERT_EQ(second_drawn.size(), second_expected.size());
      size_t differ[2] = {0, 0};
      for (size_t p = 0; p < main_drawn.size(); ++p) {
        differ[0] += main_drawn[p] != main_expected[p];
        differ[1] += second_drawn[p] != second_expected[p];
        moving += f > 0 && glm::length(second_expected[p]) > 1e-3f;
      }
      EXPECT_EQ(differ[0], 0u) << "main view";
      EXPECT_EQ(differ[1], 0u) << "second view";
    }
  }
  EXPECT_GT(moving, 100u) << "the second view's characters move on screen";
  target.restore();
  target.release();
}

// What a view keeps on the GPU lasts while it is drawn: its LOD hysteresis holds an instance at
// LOD 1 inside the band round the line. Past 32 views the least recently drawn starts over, from
// its CPU LODs (0 here), and the same draw then picks LOD 0.
TEST_P(GpuViews, TheLeastRecentlyDrawnViewPast32StartsOver) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  InstanceDesc one;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(one, &h).isOk());
  const CullParams p = CrowdExport::cullParams(crowd.view(), closeCamera());
  const double line = double(p.lod_lines[0]) * double(p.radius);
  const auto at = [](double distance) {  // Looking at the instance from `distance` away.
    return Camera::lookAt({0.0, 0.0, distance}, {0.0, 0.0, 0.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f,
                          0.1f, 500.0f);
  };
  const auto lod = [&](const CrowdView& view, double distance) {
    DrawStats stats;
    EXPECT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, view, at(distance), &stats).isOk());
    std::vector<glm::uvec2> selection;
    EXPECT_TRUE(r.readGpuSelection(CharacterId{}, &selection).isOk());
    return selection.size() == 1 ? selection[0].y : 99u;
  };
  for (const uint32_t others : {31u, 32u}) {
    SCOPED_TRACE(others);
    CrowdView view;
    std::vector<CrowdView> rest(others);
    ASSERT_TRUE(view.init(crowd).isOk());
    for (CrowdView& v : rest) ASSERT_TRUE(v.init(crowd).isOk());
    ASSERT_TRUE(crowd.advance(0.1).isOk());
    EXPECT_EQ(lod(view, line * 1.2), 1u);  // Past the line and its band.
    ASSERT_TRUE(crowd.advance(0.1).isOk());
    EXPECT_EQ(lod(view, line), 1u);  // Inside the band: held.
    for (CrowdView& v : rest) lod(v, line);
    EXPECT_EQ(lod(view, line), others < 32 ? 1u : 0u);
  }
}

// A detached view is refused by name; kRigid is refused.
TEST_P(GpuViews, ADetachedViewAndRigidAreRefused) {
  Renderer r;
  makeRenderer(&r);
  CrowdView view;
  DrawStats stats;
  const Status s = r.drawCrowdGpuCulled(CharacterId{}, view, closeCamera(), &stats);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("not attached"), std::string::npos) << s.message();
  CrowdManager crowd;
  makeCrowd(&crowd);
  EXPECT_EQ(
      r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), &stats, DrawMode::kRigid)
          .code(),
      StatusCode::kInvalidArgument);
}

INSTANTIATE_TEST_SUITE_P(Backends, GpuViews, test::allBackends(), test::backendTestName);

}  // namespace
}  // namespace si
