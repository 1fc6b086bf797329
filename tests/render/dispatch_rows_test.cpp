// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Compute passes past GL_MAX_COMPUTE_WORK_GROUP_COUNT's x: with the context's group count in x
// lowered to 1 (GlInfo, as a context with a small limit would report it), every pass lays its
// groups out in rows, and the compute path, the capture and both GPU-driven draws give exactly
// what they give within one row. The sizes where a real context needs rows (65535 x 64 vertices
// or instances) are the GPU-free dispatch grid tests' (tests/gl/dispatch_grid_test.cpp).
#include <algorithm>

#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

class DispatchRowsTest : public RenderTest {
 protected:
  // The LOD crowd and 48 more in a band behind it: more than one group of 64 instances.
  void makeScene(CrowdManager* crowd) {
    makeCrowd(crowd);
    populateLodCrowd(crowd);
    for (int k = 0; k < 48; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k % 16 - 7.5) * 2.0, 0.0, -50.0 - 4.0 * (k / 16));
      d.clip = uint32_t(k) % uint32_t(palette().clips.size());
      d.time_seconds = 0.05 * k;
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
    }
    ASSERT_TRUE(crowd->update(0.2, lodCamera()).isOk());
  }

  // What each compute pass draws or captures with `info`.
  struct Output {
    std::vector<uint8_t> compute, gpu_driven, gpu_driven_preskinned;
    std::vector<glm::vec3> captured;
    std::vector<glm::uvec2> selection;
  };
  void drawAll(const GlInfo& info, const CrowdManager& crowd, Output* out) {
    Renderer r;
    makeRenderer(&r, info);
    out->compute = draw(r, crowd, lodCamera(), 0, false, nullptr, Path::kCompute);
    for (DrawMode mode : {DrawMode::kSkinned, DrawMode::kComputeSkinned}) {
      r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      const Status s =
          r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), nullptr, mode);
      ASSERT_TRUE(s.isOk()) << s.toString();
      ASSERT_TRUE(context_->readPixels(mode == DrawMode::kSkinned ? &out->gpu_driven
                                                                  : &out->gpu_driven_preskinned)
                      .isOk());
    }
    ASSERT_TRUE(r.readGpuSelection(si::CharacterId{}, &out->selection).isOk());
    std::sort(out->selection.begin(), out->selection.end(),
              [](const glm::uvec2& a, const glm::uvec2& b) {
                return a.x != b.x ? a.x < b.x : a.y < b.y;
              });
    ASSERT_TRUE(r.captureSkinnedPositions(CharacterId{}, crowd.view().records()[0], &out->captured,
                                          SkinningPath::kCompute)
                    .isOk());
  }
};

TEST_P(DispatchRowsTest, EveryComputePassGivesTheSameResultInRowsOfOneGroup) {
  CrowdManager crowd;
  makeScene(&crowd);
  ASSERT_GT(crowd.view().records().size(), 64u);  // The cull and scatter passes need 2+ groups.
  Output one_row, rows;
  drawAll(info_, crowd, &one_row);
  GlInfo narrow = info_;
  narrow.max_compute_groups_x = 1;
  drawAll(narrow, crowd, &rows);
  EXPECT_EQ(rows.selection, one_row.selection);
  EXPECT_EQ(rows.selection.size(), crowd.view().records().size());
  EXPECT_EQ(rows.captured, one_row.captured);
  EXPECT_EQ(compare(rows.compute, one_row.compute, nullptr).share, 0.0);
  EXPECT_EQ(compare(rows.gpu_driven, one_row.gpu_driven, nullptr).share, 0.0);
  EXPECT_EQ(compare(rows.gpu_driven_preskinned, one_row.gpu_driven_preskinned, nullptr).share,
            0.0);
  // The images are the crowd's, not empty ones alike.
  EXPECT_GT(compare(one_row.compute, std::vector<uint8_t>(one_row.compute.size(), 0), nullptr)
                .share,
            0.5);
}

TEST_P(DispatchRowsTest, APassPastBothLimitsIsRefusedByName) {
  CrowdManager crowd;
  makeScene(&crowd);
  GlInfo tiny = info_;
  tiny.max_compute_groups_x = 1;
  tiny.max_compute_groups_y = 1;  // At most 64 instances per cull pass.
  Renderer r;
  makeRenderer(&r, tiny);
  const Status s = r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), nullptr);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("GL_MAX_COMPUTE_WORK_GROUP_COUNT"), std::string::npos)
      << s.message();
  std::vector<glm::vec3> positions;  // The character's vertices need many groups: 1 x 1 is too few.
  EXPECT_EQ(r.captureSkinnedPositions(CharacterId{}, crowd.view().records()[0], &positions,
                                      SkinningPath::kCompute)
                .code(),
            StatusCode::kLimitExceeded);
  EXPECT_TRUE(checkGlErrors("refused passes").isOk());  // Refused before any GL call.
}

INSTANTIATE_TEST_SUITE_P(Backends, DispatchRowsTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
