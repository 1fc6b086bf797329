// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Morph targets from glTF (issue "Any animated glTF becomes a crowd", part 1): a mesh's targets
// and the weights channel that animates them import sparsely, placed as the surface is; the
// reference then poses them exactly as the file, evaluated here independently in double
// precision (tests/gltf/morph_asset.h), says: within 1e-6 of the character's height.
#include <gtest/gtest.h>

#include "gltf/import_json.h"
#include "gltf/morph_asset.h"
#include "si/bake/animation_baker.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {

using namespace test;

TEST(GltfMorphTargets, TargetsImportSparselyPlacedByTheirNode) {
  Character c;
  GltfImportReport r;
  const Status s = importJson(morphFile("LINEAR"), &c, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  ASSERT_EQ(c.mesh.morph_targets.size(), 3u);
  EXPECT_EQ(r.morph_targets, 3u);
  EXPECT_EQ(r.morph_target_entries, 5u);  // 2 + 2 + 1 vertices moved.
  EXPECT_EQ(r.dropped_morph_targets, 0u);
  const MorphTarget& raise = c.mesh.morph_targets[0];
  const MorphTarget& widen = c.mesh.morph_targets[1];
  const MorphTarget& blink = c.mesh.morph_targets[2];
  EXPECT_EQ(raise.name, "raise");
  EXPECT_EQ(widen.name, "widen");
  EXPECT_EQ(blink.name, "blink");
  EXPECT_EQ(raise.vertices, (std::vector<uint32_t>{2, 3}));
  EXPECT_EQ(widen.vertices, (std::vector<uint32_t>{1, 2}));
  EXPECT_EQ(blink.vertices, (std::vector<uint32_t>{0}));
  EXPECT_EQ(raise.normal_deltas.size(), 2u);
  EXPECT_TRUE(raise.tangent_deltas.empty());  // All zero: not kept.
  EXPECT_TRUE(widen.normal_deltas.empty());
  EXPECT_EQ(widen.tangent_deltas.size(), 2u);
  EXPECT_FLOAT_EQ(raise.default_weight, 0.0f);
  EXPECT_FLOAT_EQ(blink.default_weight, 0.75f);
  // Deltas turn and scale with the node (90 degrees about Y, times 2): +Z 0.5 becomes +X 1.
  EXPECT_NEAR(raise.position_deltas[0].x, 1.0f, 1e-6f);
  EXPECT_NEAR(raise.position_deltas[0].z, 0.0f, 1e-6f);
  ASSERT_EQ(c.clips.size(), 2u);
  ASSERT_EQ(c.clips[0].morph_tracks.size(), 1u);
  const MorphWeightTrack& track = c.clips[0].morph_tracks[0];
  EXPECT_EQ(track.first_target, 0u);
  EXPECT_EQ(track.target_count, 3u);
  EXPECT_EQ(track.interpolation, Interpolation::kLinear);
  EXPECT_FLOAT_EQ(c.clips[0].duration_seconds, 2.0f);
  EXPECT_TRUE(c.clips[1].morph_tracks.empty());
}

// The reference (evaluatePose, evaluateMorphWeights, skinVertices) against the file evaluated
// here, for each interpolation, at keys, between them and past the end.
void expectReferenceMatches(const std::string& interpolation) {
  SCOPED_TRACE(interpolation);
  Character c;
  const Status s = importJson(morphFile(interpolation), &c);
  ASSERT_TRUE(s.isOk()) << s.toString();
  const double height = c.height();
  ASSERT_GT(height, 1.0);
  const Clip& clip = c.clips[0];
  for (double t : {0.0, 0.3, 1.0, 1.25, 1.7, 2.0}) {
    ReferencePose pose;
    ASSERT_TRUE(evaluateLocalPose(c.skeleton, clip, t, &pose).isOk());
    std::vector<double> w(3);
    ASSERT_TRUE(evaluateMorphWeights(c.mesh, clip, t, w).isOk());
    std::vector<double> want_w(3);
    for (size_t k = 0; k < 3; ++k) {
      want_w[k] = expectedMorphWeight(interpolation, k, t);
      EXPECT_NEAR(w[k], want_w[k], 1e-6) << "t " << t << " target " << k;
    }
    std::vector<glm::dvec3> pos(4), nrm(4);
    std::vector<glm::dvec4> tan(4);
    ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, pos, nrm, tan, w).isOk());
    const ExpectedMorph want = expectedMorph(want_w);
    for (size_t v = 0; v < 4; ++v) {
      EXPECT_LE(glm::distance(pos[v], want.positions[v]), 1e-6 * height) << "t " << t << " v " << v;
      EXPECT_LE(glm::distance(nrm[v], want.normals[v]), 1e-6) << "t " << t << " v " << v;
      EXPECT_LE(glm::distance(glm::dvec3(tan[v]), want.tangents[v]), 1e-6)
          << "t " << t << " v " << v;
    }
  }
}

TEST(GltfMorphTargets, TheReferencePosesLinearWeightsAsTheFileSays) {
  expectReferenceMatches("LINEAR");
}
TEST(GltfMorphTargets, TheReferencePosesStepWeightsAsTheFileSays) {
  expectReferenceMatches("STEP");
}
TEST(GltfMorphTargets, TheReferencePosesCubicSplineWeightsAsTheFileSays) {
  expectReferenceMatches("CUBICSPLINE");
}

TEST(GltfMorphTargets, AClipWithoutAWeightsChannelTakesTheDefaultWeights) {
  Character c;
  ASSERT_TRUE(importJson(morphFile("LINEAR"), &c).isOk());
  std::vector<double> w(3);
  ASSERT_TRUE(evaluateMorphWeights(c.mesh, c.clips[1], 0.5, w).isOk());
  EXPECT_EQ(w, (std::vector<double>{0.0, 0.0, 0.75}));
  // skinVertices without weights takes the same defaults.
  ReferencePose pose;
  ASSERT_TRUE(evaluateLocalPose(c.skeleton, c.clips[1], 0.5, &pose).isOk());
  std::vector<glm::dvec3> with(4), without(4);
  ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, with, {}, {}, w).isOk());
  ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, without, {}, {}).isOk());
  EXPECT_EQ(with, without);
  const ExpectedMorph want = expectedMorph({0.0, 0.0, 0.75});
  EXPECT_LE(glm::distance(without[0], want.positions[0]), 1e-6);
}

TEST(GltfMorphTargets, NodeWeightsWinOverTheMeshs) {
  std::string json = morphFile("LINEAR");
  const std::string node = "\"name\":\"face\",\"mesh\":0,";
  const size_t at = json.find(node);
  ASSERT_NE(at, std::string::npos);
  json.insert(at + node.size(), "\"weights\":[0.5,0.25,0],");
  Character c;
  ASSERT_TRUE(importJson(json, &c).isOk());
  EXPECT_FLOAT_EQ(c.mesh.morph_targets[0].default_weight, 0.5f);
  EXPECT_FLOAT_EQ(c.mesh.morph_targets[1].default_weight, 0.25f);
  EXPECT_FLOAT_EQ(c.mesh.morph_targets[2].default_weight, 0.0f);
}

TEST(GltfMorphTargets, KeptByDefaultOrDroppedWithAWarningEach) {
  Character kept;
  ASSERT_TRUE(importJson(morphFile("LINEAR"), &kept).isOk());
  EXPECT_EQ(kept.mesh.morph_targets.size(), 3u);
  Character c;
  GltfImportReport r;
  GltfImportDesc drop;
  drop.keep_morph_targets = false;
  ASSERT_TRUE(importJson(morphFile("LINEAR"), &c, &r, drop).isOk());
  EXPECT_TRUE(c.mesh.morph_targets.empty());
  EXPECT_TRUE(c.clips[0].morph_tracks.empty());
  EXPECT_EQ(r.dropped_morph_targets, 3u);
  EXPECT_EQ(r.morph_targets, 0u);
  const auto warned = [&](const char* what) {
    for (const std::string& w : r.warnings)
      if (w.find(what) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(warned("3 morph targets dropped"));
  EXPECT_TRUE(warned("which has no morph targets (or they were dropped): skipped"));
}

TEST(GltfMorphTargets, EachInterpolationBakesWithinTheTolerance) {
  for (const char* interp : {"LINEAR", "STEP", "CUBICSPLINE"}) {
    SCOPED_TRACE(interp);
    Character c;
    ASSERT_TRUE(importJson(morphFile(interp), &c).isOk());
    BakedPalette p;
    BakeReport r;
    const Status s = bakePalette(c, BakeDesc(), &p, &r);
    ASSERT_TRUE(s.isOk()) << s.toString();
    EXPECT_EQ(p.layout.morph_target_count, 3u);
    for (const ClipErrorReport& clip : r.clips) {
      EXPECT_TRUE(clip.tolerance_met) << clip.name;
      EXPECT_LE(clip.max_error_ratio, 1e-4) << clip.name;
    }
  }
}

TEST(GltfMorphTargets, MalformedTargetsAreRefusedByName) {
  Character c;
  GltfImportReport r;
  // Two default weights for three targets.
  Status s = importJson(morphFile("LINEAR", "[0,0.5]"), &c, &r);
  EXPECT_EQ(s.code(), StatusCode::kCorrupt);
  EXPECT_NE(s.message().find("2 default weights for 3 morph targets"), std::string::npos)
      << s.toString();
  // A weights channel whose output is not keys x targets.
  std::string json = morphFile("LINEAR");
  const std::string linear = "\"interpolation\":\"LINEAR\"";
  json.replace(json.find(linear), linear.size(), "\"interpolation\":\"CUBICSPLINE\"");
  s = importJson(json, &c, &r);
  EXPECT_EQ(s.code(), StatusCode::kCorrupt);
  EXPECT_NE(s.message().find("9 output weights for 3 key times of 3 morph targets"),
            std::string::npos)
      << s.toString();
}

}  // namespace
}  // namespace si
