// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A vertex with 8 influences keeps its 4 largest: the import reports, per vertex, how far that
// moves it over the clip's poses, against the test's own double-precision skinning.
#include <gtest/gtest.h>

#include <algorithm>

#include <limits>

#include "gltf/eight_influence_asset.h"
#include "gltf/import_json.h"
#include "si/bake/animation_baker.h"
#include "si/core/reference_evaluator.h"
#include "si/gltf/gltf_import.h"

namespace si {
namespace {

using test::importJson;

GltfImportDesc alwaysFold() {
  GltfImportDesc d;
  d.fold_tolerance_height = std::numeric_limits<float>::infinity();
  return d;
}

TEST(GltfInfluenceFold, EachFoldedVertexReportsHowFarItsFourInfluencesMoveIt) {
  test::EightInfluenceFan fan;
  Character c;
  GltfImportReport r;
  const Status s = importJson(fan.file(), &c, &r, alwaysFold());
  ASSERT_TRUE(s.isOk()) << s.toString();
  EXPECT_FALSE(r.kept_eight_influences);
  EXPECT_TRUE(c.mesh.joints1.empty());
  ASSERT_EQ(r.folded_vertices.size(), 3u);  // Vertex 3's second set is all zero.
  double largest = 0.0;
  for (int v = 0; v < 3; ++v) {
    // The clip at 30 Hz: 0, 1/30, ..., 1 s (the rest pose is its first sample).
    double expected = 0.0;
    for (int i = 0; i <= 30; ++i)
      expected = std::max(
          expected, glm::length(fan.skinned(v, i / 30.0, true) - fan.skinned(v, i / 30.0, false)));
    const GltfImportReport::FoldedVertex& f = r.folded_vertices[size_t(v)];
    EXPECT_EQ(f.vertex, uint32_t(v));
    EXPECT_NEAR(f.dropped_weight, 0.24f, 1e-6f) << v;
    EXPECT_GT(expected, 0.01) << v;  // A fold that matters.
    EXPECT_NEAR(f.error_units, expected, 1e-6 * expected) << v;
    largest = std::max(largest, expected);
  }
  EXPECT_NEAR(r.max_fold_error_units, largest, 1e-6 * largest);
  EXPECT_NEAR(r.max_fold_error_height, largest / 2.0, 1e-6 * largest);  // 2 units tall.
  EXPECT_NEAR(r.max_dropped_weight, 0.24f, 1e-6f);
  EXPECT_EQ(r.fold_sample_hz, 30.0);
  EXPECT_TRUE(std::any_of(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
    return w.find("3 vertices have more than 4 influences") != std::string::npos;
  }));
}

// A clip that would take more poses than the import measures is sampled evenly slower, its end
// still among them: the report says the rate, and the fan's largest fold (at the clip's end,
// where the bones have turned furthest) is still found.
TEST(GltfInfluenceFold, LongClipsAreSampledSlowerAndSaySo) {
  test::EightInfluenceFan fan;
  fan.duration = 1000.0f;  // 30,001 poses at 30 Hz.
  Character c;
  GltfImportReport r;
  ASSERT_TRUE(importJson(fan.file(), &c, &r, alwaysFold()).isOk());
  EXPECT_GT(r.fold_sample_hz, 0.0);
  EXPECT_LE(r.fold_sample_hz * 1000.0, 4096.0);
  ASSERT_EQ(r.folded_vertices.size(), 3u);
  for (int v = 0; v < 3; ++v) {
    const double at_end = glm::length(fan.skinned(v, 1.0, true) - fan.skinned(v, 1.0, false));
    EXPECT_NEAR(r.folded_vertices[size_t(v)].error_units, at_end, 1e-6 * at_end) << v;
  }
}

// Without a second set, or with one whose weights are all zero, nothing is folded or reported.
TEST(GltfInfluenceFold, NothingFoldedNothingReported) {
  test::EightInfluenceFan fan;
  fan.second_set_zero = true;
  Character c;
  GltfImportReport r;
  ASSERT_TRUE(importJson(fan.file(), &c, &r).isOk());
  EXPECT_TRUE(r.folded_vertices.empty());
  EXPECT_EQ(r.max_fold_error_units, 0.0);
  EXPECT_EQ(r.fold_sample_hz, 0.0);
  EXPECT_EQ(r.max_dropped_weight, 0.0f);
}

// Past the tolerance (the default: the bake's, 1e-4 of the height; the fan's fold costs 0.067)
// the character keeps all 8 influences: the reference skins the imported mesh where the test's
// own 8-influence skinning puts it, and the default bake measures against that and meets its
// tolerance. Exactly at the fold's error it still folds; a tolerance that is not a number or
// negative is refused.
TEST(GltfInfluenceFold, PastTheToleranceAllEightAreKept) {
  test::EightInfluenceFan fan;
  Character c;
  GltfImportReport r;
  ASSERT_TRUE(importJson(fan.file(), &c, &r).isOk());
  EXPECT_TRUE(r.kept_eight_influences);
  ASSERT_EQ(c.mesh.joints1.size(), c.mesh.vertexCount());
  EXPECT_TRUE(std::any_of(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
    return w.find("kept all 8 influences") != std::string::npos;
  }));
  for (double t : {0.0, 0.5, 1.0}) {
    ReferencePose pose;
    ASSERT_TRUE(evaluateLocalPose(c.skeleton, c.clips[0], t, &pose).isOk());
    std::vector<glm::dvec3> positions(c.mesh.vertexCount());
    ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, positions, {}, {}).isOk());
    for (int v = 0; v < test::EightInfluenceFan::kVertices; ++v)
      EXPECT_LT(glm::length(positions[size_t(v)] - fan.skinned(v, t, false)), 2e-6)
          << v << " at " << t;
  }
  BakedPalette palette;
  BakeReport bake;
  const Status baked = bakePalette(c, BakeDesc(), &palette, &bake);
  ASSERT_TRUE(baked.isOk()) << baked.toString();
  EXPECT_LE(bake.max_error_ratio, 1e-4);

  GltfImportDesc at_the_error;
  at_the_error.fold_tolerance_height = float(r.max_fold_error_height) * 1.001f;
  Character folded;
  GltfImportReport folded_report;
  ASSERT_TRUE(importJson(fan.file(), &folded, &folded_report, at_the_error).isOk());
  EXPECT_FALSE(folded_report.kept_eight_influences);
  EXPECT_TRUE(folded.mesh.joints1.empty());
  for (float bad : {-1.0f, std::numeric_limits<float>::quiet_NaN()}) {
    GltfImportDesc d;
    d.fold_tolerance_height = bad;
    EXPECT_EQ(importJson(fan.file(), &folded, &folded_report, d).code(),
              StatusCode::kInvalidArgument);
  }
}

}  // namespace
}  // namespace si
