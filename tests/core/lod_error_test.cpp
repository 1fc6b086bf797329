// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// LOD geometric error: distances to a surface against closed forms and brute force; measured
// LOD errors on the embedded character; per-level errors for the crowd.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "si/core/default_character.h"
#include "si/core/lod_error.h"

namespace si {
namespace {

// Two triangles making the unit square in z = 0.
const std::vector<glm::vec3> kSquare = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                        {0, 0, 0.1f}, {1, 0, 0.1f}, {1, 1, 0.1f}, {0, 1, 0.1f}};
const std::vector<uint32_t> kLow = {0, 1, 2, 0, 2, 3}, kHigh = {4, 5, 6, 4, 6, 7};

TEST(LodError, DistancesToASquareFollowTheClosedForm) {
  float d = 0.0f;
  const std::vector<glm::vec3> above = {{0.5f, 0.5f, 0.5f}};
  ASSERT_TRUE(maxDistanceToSurface(kSquare, kLow, above, &d).isOk());
  EXPECT_NEAR(d, 0.5f, 1e-6f);
  const std::vector<glm::vec3> corner = {{2.0f, 2.0f, 0.0f}, {0.2f, 0.3f, 0.0f}};
  ASSERT_TRUE(maxDistanceToSurface(kSquare, kLow, corner, &d).isOk());
  EXPECT_NEAR(d, std::sqrt(2.0f), 1e-6f);  // The corner (1, 1, 0); the other point lies on it.
  ASSERT_TRUE(maxDistanceToSurface(kSquare, kLow, {}, &d).isOk());
  EXPECT_EQ(d, 0.0f);
  ASSERT_TRUE(surfaceDistance(kSquare, kLow, kHigh, &d).isOk());
  EXPECT_NEAR(d, 0.1f, 1e-6f);
  ASSERT_TRUE(surfaceDistance(kSquare, kLow, kLow, &d).isOk());
  EXPECT_NEAR(d, 0.0f, 1e-6f);  // Centroids on the surface: float round-off only.
}

TEST(LodError, BadSurfacesAreErrors) {
  float d = -1.0f;
  const std::vector<uint32_t> out_of_range = {0, 1, 8};
  EXPECT_EQ(maxDistanceToSurface(kSquare, out_of_range, kSquare, &d).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(maxDistanceToSurface(kSquare, {}, kSquare, &d).code(), StatusCode::kInvalidArgument);
  const std::vector<uint32_t> partial = {0, 1};
  EXPECT_EQ(surfaceDistance(kSquare, kLow, partial, &d).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(maxDistanceToSurface(kSquare, kLow, kSquare, nullptr).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(d, -1.0f);
}

// The grid search finds what trying every triangle finds.
TEST(LodError, GridSearchEqualsBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> positions(300);
  for (glm::vec3& p : positions) p = glm::vec3(u(rng) * 3.0f, u(rng) * 0.2f, u(rng));  // Flat-ish.
  std::vector<uint32_t> tris;
  for (uint32_t t = 0; t < 120; ++t)
    for (int k = 0; k < 3; ++k) tris.push_back(uint32_t(rng() % positions.size()));
  std::vector<glm::vec3> points(150);
  for (glm::vec3& p : points) p = glm::vec3(u(rng) * 4.0f, u(rng) * 2.0f, u(rng) * 2.0f);
  for (const glm::vec3& p : points) {
    float grid = 0.0f;
    ASSERT_TRUE(maxDistanceToSurface(positions, tris, Span<const glm::vec3>(&p, 1), &grid).isOk());
    float brute = std::numeric_limits<float>::max();
    for (size_t t = 0; t < tris.size(); t += 3) {
      // Distance to the triangle by dense barycentric sampling (a bound from above) and the
      // grid's own answer must agree within the sampling step.
      for (int i = 0; i <= 24; ++i)
        for (int j = 0; i + j <= 24; ++j) {
          const float a = i / 24.0f, b = j / 24.0f;
          const glm::vec3 q = positions[tris[t]] * (1.0f - a - b) + positions[tris[t + 1]] * a +
                              positions[tris[t + 2]] * b;
          brute = std::min(brute, glm::length(p - q));
        }
    }
    EXPECT_LE(grid, brute + 1e-5f);  // Never above a point of the surface (a search cut short).
    EXPECT_GE(grid, brute - 0.25f);  // The sampling step bounds how far above the truth it is.
  }
}

TEST(LodError, TheEmbeddedCharactersLodsCarryMeasuredErrors) {
  Character c;
  ASSERT_TRUE(makeDefaultCharacter({}, &c).isOk());
  for (const SubMesh& sm : c.mesh.sub_meshes) {
    ASSERT_EQ(sm.lod_error_units.size(), sm.lods.size()) << sm.name;
    EXPECT_EQ(sm.lod_error_units[0], 0.0f);
    for (size_t l = 1; l < sm.lods.size(); ++l) {
      EXPECT_GT(sm.lod_error_units[l], 0.0f) << sm.name << " LOD " << l;
      EXPECT_LT(sm.lod_error_units[l], 0.05f * c.height()) << sm.name << " LOD " << l;
    }
  }
  // Measuring again gives the same figures; without overwrite nothing changes.
  SkinnedMesh again = c.mesh;
  for (SubMesh& sm : again.sub_meshes) sm.lod_error_units.assign(sm.lods.size(), 7.0f);
  ASSERT_TRUE(measureLodErrors(&again, false).isOk());
  EXPECT_EQ(again.sub_meshes[0].lod_error_units[1], 7.0f);
  ASSERT_TRUE(measureLodErrors(&again, true).isOk());
  EXPECT_EQ(again.sub_meshes[0].lod_error_units, c.mesh.sub_meshes[0].lod_error_units);
  // An invalid mesh is an error and stays as it was.
  SkinnedMesh broken = c.mesh;
  broken.indices.push_back(0);
  EXPECT_FALSE(measureLodErrors(&broken, true).isOk());
  EXPECT_EQ(broken.sub_meshes[0].lod_error_units, c.mesh.sub_meshes[0].lod_error_units);
}

TEST(LodError, LevelErrorsAreTheWorstSubMeshAndNeverDecrease) {
  SkinnedMesh m;
  m.positions = kSquare;
  m.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6};
  m.sub_meshes.push_back(SubMesh{"a", {{0, 6}, {0, 3}, {6, 3}}, 0, {0.0f, 0.5f, 0.2f}});
  m.sub_meshes.push_back(SubMesh{"b", {{0, 3}, {6, 3}}, 0, {0.0f, 0.3f}});
  std::vector<float> levels;
  ASSERT_TRUE(lodErrorsByLevel(m, &levels).isOk());
  ASSERT_EQ(levels.size(), 3u);
  EXPECT_EQ(levels[0], 0.0f);
  EXPECT_EQ(levels[1], 0.5f);
  EXPECT_EQ(levels[2], 0.5f);  // a's 0.2 and b's last level (0.3) do not lower it.
  m.sub_meshes[1].lod_error_units.clear();
  EXPECT_EQ(lodErrorsByLevel(m, &levels).code(), StatusCode::kInvalidArgument);
}

TEST(LodError, LevelSummaryCountsWhatInstancesDraw) {
  Character c;
  ASSERT_TRUE(makeDefaultCharacter({}, &c).isOk());
  // A sub-mesh with fewer levels draws its last one at the coarser levels.
  c.mesh.sub_meshes[1].lods.resize(1);
  c.mesh.sub_meshes[1].lod_error_units.resize(1);
  std::vector<LodLevelSummary> levels;
  ASSERT_TRUE(summarizeLodLevels(c.mesh, &levels).isOk());
  std::vector<float> errors;
  ASSERT_TRUE(lodErrorsByLevel(c.mesh, &errors).isOk());
  ASSERT_EQ(levels.size(), c.mesh.maxLodCount());
  for (size_t l = 0; l < levels.size(); ++l) {
    uint64_t triangles = 0;
    for (size_t sm = 0; sm < c.mesh.sub_meshes.size(); ++sm)
      triangles += c.mesh.triangleCount(sm, std::min(l, c.mesh.sub_meshes[sm].lods.size() - 1));
    EXPECT_EQ(levels[l].triangles, triangles) << l;
    EXPECT_EQ(levels[l].error_units, errors[l]) << l;
  }
  EXPECT_GT(levels[0].triangles, levels[2].triangles);
  EXPECT_EQ(summarizeLodLevels(c.mesh, nullptr).code(), StatusCode::kInvalidArgument);
  c.mesh.sub_meshes[0].lod_error_units.clear();  // Not measured: named.
  EXPECT_EQ(summarizeLodLevels(c.mesh, &levels).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace si
