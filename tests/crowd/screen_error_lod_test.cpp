#include "si/crowd/crowd_export.h"
// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Screen-space-error LOD: each instance gets the coarsest LOD whose error, projected at its
// distance, stays within the pixel budget, whatever its scale; the budget, the viewport and the
// field of view move the choice as the projection says; validity of the desc and setLodMode.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "crowd/crowd_test_helpers.h"

namespace si {
namespace {

using test::defaultPalette;

constexpr float kErrors[4] = {0.0f, 0.02f, 0.08f, 0.3f};

CrowdDesc screenErrorDesc(float budget) {
  CrowdDesc d;
  d.palette = &defaultPalette();
  d.sub_mesh_count = 1;
  d.lod_count = 4;
  d.lod_mode = LodMode::kScreenError;
  d.lod_errors_units.assign(kErrors, kErrors + 4);
  d.pixel_error_budget = budget;
  d.lod_hysteresis_ratio = 1e-6f;  // As good as none, to test the lines themselves.
  d.max_distance_radii = -1.0f;    // No far line.
  return d;
}

// A camera at the origin looking down -z, 60 degrees vertically, 1000 pixels tall.
Camera camera(float viewport = 1000.0f, float fov = 1.0471976f) {
  Camera c = Camera::lookAt({0, 0, 0}, {0, 0, -1}, glm::vec3(0, 1, 0), fov, 1.0f, 0.1f, 1e5f);
  c.viewport_height_pixels = viewport;
  return c;
}

// The expected LOD: the coarsest whose projected error is within the budget.
uint32_t expectedLod(double distance, float scale, float budget, const Camera& cam) {
  const double k = 0.5 * cam.viewport_height_pixels * std::fabs(cam.projection[1][1]);
  uint32_t lod = 0;
  for (uint32_t l = 1; l < 4; ++l)
    if (kErrors[l] * scale * k / distance <= budget) lod = l;
  return lod;
}

void expectLods(float budget, const Camera& cam) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(screenErrorDesc(budget)).isOk());
  std::vector<std::pair<InstanceHandle, uint32_t>> expected;
  for (float scale : {0.5f, 1.0f, 2.0f})
    for (double d = 2.0; d < 5000.0; d *= 1.13) {
      // Skip distances within 0.1 % of a line: the hysteresis margin.
      const uint32_t lo = expectedLod(d * 0.999, scale, budget, cam);
      if (lo != expectedLod(d * 1.001, scale, budget, cam)) continue;
      InstanceDesc desc;
      desc.position = glm::dvec3(0.0, 0.0, -d);
      desc.scale = scale;
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(desc, &h).isOk());
      expected.push_back({h, lo});
    }
  ASSERT_TRUE(crowd.update(0.0, cam).isOk());
  uint32_t seen[4] = {0, 0, 0, 0};
  for (const auto& [h, lod] : expected) {
    uint32_t got = 0;
    ASSERT_TRUE(crowd.view().lodOf(h, &got).isOk());
    EXPECT_EQ(got, lod);
    ++seen[got];
  }
  for (uint32_t l = 0; l < 4; ++l) EXPECT_GT(seen[l], 0u) << "no instance at LOD " << l;
}

TEST(ScreenErrorLod, TheCoarsestLodWithinTheBudgetWhateverTheScale) {
  expectLods(1.0f, camera());
  expectLods(0.5f, camera());
  expectLods(4.0f, camera());
  expectLods(1.0f, camera(2160.0f));            // A taller viewport: finer at a distance.
  expectLods(1.0f, camera(1000.0f, 0.3f));      // A narrow field of view: finer too.
}

// A y-flipped projection (a render texture) selects what the upright one does (it selected
// LOD 0 everywhere); an orthographic one (a shadow cascade) selects by the projected error
// alone, the same level at every distance (it selected by distance lines).
TEST(ScreenErrorLod, FlippedAndOrthographicProjectionsProjectTheError) {
  Camera flipped = camera();
  flipped.projection[1][1] = -flipped.projection[1][1];
  ASSERT_TRUE(flipped.flipsWinding());
  expectLods(1.0f, flipped);
  // Half the orthographic height in units, and the level expected on 1000 pixels at a budget of
  // one pixel: an error e covers e x 500 / half pixels (kErrors 0.02, 0.08, 0.3).
  const std::pair<float, uint32_t> cases[] = {{1.0f, 0u}, {20.0f, 1u}, {100.0f, 2u}, {1000.0f, 3u}};
  for (const auto& [half, lod] : cases) {
    SCOPED_TRACE(half);
    const Camera ortho =
        Camera::fromMatrices(glm::dmat4(1.0), glm::ortho(-half, half, -half, half, 0.1f, 1e5f),
                             DepthConvention::kNegativeOneToOne, 1000.0f);
    CrowdManager crowd;
    ASSERT_TRUE(crowd.init(screenErrorDesc(1.0f)).isOk());
    std::vector<InstanceHandle> handles;
    for (double d = 2.0; d < 5000.0; d *= 1.5) {
      InstanceDesc desc;
      desc.position = glm::dvec3(0.0, 0.0, -d);
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(desc, &h).isOk());
      handles.push_back(h);
    }
    ASSERT_TRUE(crowd.update(0.0, ortho).isOk());
    for (InstanceHandle h : handles) {
      uint32_t got = 9;
      ASSERT_TRUE(crowd.view().lodOf(h, &got).isOk());
      EXPECT_EQ(got, lod);
    }
  }
}

TEST(ScreenErrorLod, ABudgetTwiceAsLargeHalvesTheDistances) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(screenErrorDesc(1.0f)).isOk());
  const Camera cam = camera();
  const CullParams one = CrowdExport::cullParams(crowd.view(), cam);
  ASSERT_TRUE(crowd.setLodMode(LodMode::kScreenError, 2.0f).isOk());
  const CullParams two = CrowdExport::cullParams(crowd.view(), cam);
  for (int l = 0; l < 3; ++l) {
    EXPECT_GT(one.lod_lines[l], 0.0f);
    EXPECT_NEAR(two.lod_lines[l], 0.5f * one.lod_lines[l], 1e-5f * one.lod_lines[l]);
  }
  // Back to the technique's lines.
  ASSERT_TRUE(crowd.setLodMode(LodMode::kDistance, 0.0f).isOk());
  EXPECT_EQ(CrowdExport::cullParams(crowd.view(), cam).lod_lines[0],
            crowd.desc().lod_distances_radii[0]);
}

TEST(ScreenErrorLod, ACameraWithoutAUsableViewportDrawsLodZero) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(screenErrorDesc(1.0f)).isOk());
  InstanceDesc desc;
  desc.position = glm::dvec3(0.0, 0.0, -1000.0);
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(desc, &h).isOk());
  for (float viewport : {0.0f, -5.0f, std::numeric_limits<float>::quiet_NaN(),
                         std::numeric_limits<float>::infinity()}) {
    ASSERT_TRUE(crowd.update(0.0, camera(viewport)).isOk());
    uint32_t lod = 9;
    ASSERT_TRUE(crowd.view().lodOf(h, &lod).isOk());
    EXPECT_EQ(lod, 0u) << "viewport " << viewport;
  }
  ASSERT_TRUE(crowd.update(0.0, camera()).isOk());
  uint32_t lod = 0;
  ASSERT_TRUE(crowd.view().lodOf(h, &lod).isOk());
  EXPECT_EQ(lod, 3u);  // Far away with a usable camera: the coarsest.
}

TEST(ScreenErrorLod, ValidityMatrix) {
  CrowdManager crowd;
  CrowdDesc d = screenErrorDesc(1.0f);
  d.lod_errors_units.clear();
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);  // Errors are required.
  d = screenErrorDesc(1.0f);
  d.lod_errors_units.pop_back();
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);  // One per LOD.
  d = screenErrorDesc(1.0f);
  d.lod_errors_units[2] = 0.01f;
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);  // Decreasing.
  d = screenErrorDesc(1.0f);
  d.lod_errors_units[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);
  d = screenErrorDesc(-1.0f);
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);
  d = screenErrorDesc(1.0f);
  d.lod_mode = LodMode(7);
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);
  // setLodMode: the same rules, and nothing changes on failure.
  CrowdDesc distance = screenErrorDesc(1.0f);
  distance.lod_mode = LodMode::kDistance;
  distance.lod_errors_units.clear();
  ASSERT_TRUE(crowd.init(distance).isOk());
  const uint64_t version = CrowdExport(crowd).stateVersion();
  EXPECT_EQ(crowd.setLodMode(LodMode::kScreenError, 1.0f).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(crowd.setLodMode(LodMode::kDistance, std::nanf("")).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(crowd.desc().lod_mode, LodMode::kDistance);
  EXPECT_EQ(CrowdExport(crowd).stateVersion(), version);
  EXPECT_STREQ(lodModeName(LodMode::kScreenError), "screen-error");
}

}  // namespace
}  // namespace si
