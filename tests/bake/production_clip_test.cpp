// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Production clips (issue "Production clips baked within tolerance in seconds"): the generated
// stress character's dense motion-capture keys, baked with the default desc, checked on every
// vertex by an emulation independent of the baker's own measurement; tolerance misses named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bake/bake_test_helpers.h"
#include "si/bake/animation_baker.h"
#include "si/core/reference_evaluator.h"
#include "stress/stress_character.h"

namespace si {
namespace {

// The stress character with a clip short enough for the default test run (its keys, mesh and
// motion are the full asset's; stress_bake measures the 32 s clip).
const Character& shortStress() {
  static const Character c = [] {
    test::StressDesc d;
    d.duration_seconds = 0.4f;
    return test::makeStressCharacter(d);
  }();
  return c;
}

// Max over `vertices` of |emulated - reference| at clip-local time t: emulateSkinning on the
// vertex format's weights against skinVertices in double (not the baker's measurement code).
double errorAt(const Character& c, const BakedPalette& p, double t,
               const std::vector<uint32_t>& vertices, const SkinnedMesh& gpu_mesh) {
  std::vector<glm::mat4> emulated(c.skeleton.jointCount());
  std::vector<glm::vec3> positions(c.mesh.vertexCount());
  std::vector<glm::dvec3> reference(c.mesh.vertexCount());
  ReferencePose pose;
  EXPECT_TRUE(emulateSkinningMatrices(p, 0, sampleFrames(p.clips[0], t), emulated).isOk());
  EXPECT_TRUE(emulateSkinning(gpu_mesh, emulated, positions, {}).isOk());
  EXPECT_TRUE(evaluateLocalPose(c.skeleton, c.clips[0], t, &pose).isOk());
  EXPECT_TRUE(skinVertices(c.mesh, pose.skinning, reference, {}, {}).isOk());
  double worst = 0.0;
  for (uint32_t v : vertices) worst = std::max(worst, glm::length(glm::dvec3(positions[v]) - reference[v]));
  return worst;
}

TEST(ProductionClips, TheStressCharacterIsWhatItsHeaderSays) {
  const Character c = test::makeStressCharacter();
  ASSERT_TRUE(c.validate().isOk());
  EXPECT_GE(c.mesh.vertexCount(), 30000u);
  EXPECT_GE(c.mesh.sub_meshes.size(), 24u);
  EXPECT_GE(c.skeleton.jointCount(), 20u);
  EXPECT_LE(c.skeleton.jointCount(), 60u);
  ASSERT_EQ(c.clips.size(), 1u);
  EXPECT_GE(c.clips[0].duration_seconds, 30.0f);
  for (const JointTracks& jt : c.clips[0].joint_tracks) {
    EXPECT_GE(jt.rotation.keyCount(), 1000u);
    EXPECT_EQ(jt.scale.keyCount(), jt.rotation.keyCount());
    EXPECT_EQ(resolveInterpolation(jt.rotation.interpolation), Interpolation::kLinear);
  }
  // Fast rotations: the bound reaches 800 degrees per second.
  EXPECT_GT(test::stressMaxAngularSpeed(), 800.0 * 3.14159265 / 180.0);
}

// The default bake meets 1e-4 of the height on every vertex at every frame interval's midpoint
// and at the worst times a dense scan of the clip finds, measured without the baker's code.
TEST(ProductionClips, TheDefaultBakeMeetsTheToleranceOnEveryVertex) {
  const Character& c = shortStress();
  BakedPalette p;
  BakeReport r;
  const Status s = bakePalette(c, BakeDesc{}, &p, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  const double tolerance = 1e-4 * c.height();
  EXPECT_TRUE(r.clips[0].tolerance_met);
  EXPECT_LE(r.clips[0].max_error_units, tolerance);
  SkinnedMesh gpu_mesh = c.mesh;
  for (glm::vec4& w : gpu_mesh.weights) w = dequantizeWeights(quantizeWeights(w));
  const std::vector<uint32_t> all = drawnVertices(c.mesh);
  const BakedClip& bc = p.clips[0];
  ASSERT_EQ(bc.frame_times_seconds.size(), bc.frame_count);
  // A dense scan (16 times per frame interval) on every 97th vertex finds the worst times...
  std::vector<uint32_t> sparse;
  for (size_t i = 0; i < all.size(); i += 97) sparse.push_back(all[i]);
  std::vector<std::pair<double, double>> scanned;  // (error, time)
  double midpoint_worst = 0.0;
  for (uint32_t f = 0; f + 1 < bc.frame_count; ++f) {
    const double a = bc.frame_times_seconds[f], b = bc.frame_times_seconds[f + 1];
    if (!(b > a)) continue;
    midpoint_worst = std::max(midpoint_worst, errorAt(c, p, 0.5 * (a + b), all, gpu_mesh));
    for (int k = 1; k < 16; k += 2) {
      const double t = a + (b - a) * k / 16.0;
      scanned.push_back({errorAt(c, p, t, sparse, gpu_mesh), t});
    }
  }
  EXPECT_LE(midpoint_worst, tolerance) << "every vertex at every midpoint";
  // ...and every vertex is measured there.
  std::sort(scanned.rbegin(), scanned.rend());
  for (size_t i = 0; i < std::min<size_t>(8, scanned.size()); ++i)
    EXPECT_LE(errorAt(c, p, scanned[i].second, all, gpu_mesh), tolerance)
        << "every vertex at t=" << scanned[i].second;
  // The baker's report saw the same worst: its max is within 5 % of the independent one.
  EXPECT_NEAR(r.clips[0].max_error_units, midpoint_worst, 0.05 * midpoint_worst);
}

// Dense keys at 37.5 Hz: a uniform grid cannot hold them (240 Hz misses by far), frames at the
// keys can.
TEST(ProductionClips, FramesSitOnEveryKeyWhereAGridMisses) {
  const Character& c = shortStress();
  BakeDesc grid;
  grid.rate_mode = RateMode::kFixed;
  grid.sample_rate_hz = 240.0f;
  BakedPalette p;
  BakeReport r;
  ASSERT_TRUE(bakePalette(c, grid, &p, &r).isOk());
  EXPECT_FALSE(r.clips[0].tolerance_met) << r.clips[0].max_error_ratio;
  ASSERT_TRUE(bakePalette(c, BakeDesc{}, &p, &r).isOk());
  EXPECT_TRUE(r.clips[0].frames_at_keys);
  EXPECT_TRUE(p.validate().isOk()) << p.validate().toString();
  const std::vector<double>& times = p.clips[0].frame_times_seconds;
  for (float k : c.clips[0].joint_tracks[7].rotation.times_seconds) {
    const auto it = std::lower_bound(times.begin(), times.end(), double(k) - 1e-9);
    ASSERT_NE(it, times.end());
    EXPECT_NEAR(*it, double(k), 1e-9) << "a frame at the key at " << k << " s";
  }
  // Each key interval is divided for its own error: not all alike.
  double shortest = 1e9, longest = 0.0;
  for (size_t i = 1; i < times.size(); ++i)
    if (times[i] > times[i - 1]) {
      shortest = std::min(shortest, times[i] - times[i - 1]);
      longest = std::max(longest, times[i] - times[i - 1]);
    }
  EXPECT_GT(longest, 1.2 * shortest);
}

// kSmaller takes cubic where it needs fewer frames at the tolerance (a grid's cut corners
// once hid that), and half floats stop near their precision floor instead of dividing every
// key interval to its limit.
TEST(ProductionClips, SmallerTakesCubicAndHalfFloatsStopAtTheirFloor) {
  const Character& c = shortStress();
  BakedPalette p;
  BakeReport linear, smaller, half;
  ASSERT_TRUE(bakePalette(c, BakeDesc{}, &p, &linear).isOk());
  BakeDesc d;
  d.interpolation = InterpolationChoice::kSmaller;
  ASSERT_TRUE(bakePalette(c, d, &p, &smaller).isOk());
  EXPECT_EQ(smaller.clips[0].interpolation, FrameInterpolation::kCubic);
  EXPECT_TRUE(smaller.clips[0].tolerance_met);
  EXPECT_LT(smaller.clips[0].frame_count, linear.clips[0].frame_count);
  BakeDesc h;
  h.format = PaletteFormat::kMatrix3x4F16;
  h.accept_tolerance_miss = true;
  ASSERT_TRUE(bakePalette(c, h, &p, &half).isOk());
  EXPECT_FALSE(half.clips[0].tolerance_met);
  EXPECT_LT(half.clips[0].frame_count, linear.clips[0].frame_count);
}

// BakeDesc::placement: a grid keeps frames uniform (and misses these keys, by name), keys
// place them at the keys; an unknown value is refused.
TEST(ProductionClips, PlacementChoosesGridOrKeys) {
  const Character& c = shortStress();
  BakedPalette p;
  BakeReport r;
  BakeDesc d;
  d.placement = FramePlacement::kGrid;
  EXPECT_EQ(bakePalette(c, d, &p, &r).code(), StatusCode::kToleranceNotMet);
  d.accept_tolerance_miss = true;
  ASSERT_TRUE(bakePalette(c, d, &p, &r).isOk());
  EXPECT_TRUE(p.clips[0].frame_times_seconds.empty());
  EXPECT_FALSE(r.clips[0].frames_at_keys);
  d.placement = FramePlacement::kKeys;
  d.accept_tolerance_miss = false;
  ASSERT_TRUE(bakePalette(c, d, &p, &r).isOk());
  EXPECT_TRUE(r.clips[0].frames_at_keys);
  EXPECT_EQ(p.clips[0].frame_times_seconds.size(), p.clips[0].frame_count);
  d.placement = static_cast<FramePlacement>(9);
  EXPECT_EQ(bakePalette(c, d, &p, &r).code(), StatusCode::kInvalidArgument);
  EXPECT_STREQ(framePlacementName(FramePlacement::kKeys), "keys");
}

// A clip keyed far more densely than it needs: frames at every key would pass the bake's work
// limit, so the default placement takes the grid (only kKeys is refused, by name).
TEST(ProductionClips, KeysPastTheLimitsFallBackToTheGrid) {
  Character c = test::chainCharacter(4);
  Clip dense = test::blankClip(c, "dense", 1.0f);
  for (int k = 0; k <= 3000; ++k) {
    dense.joint_tracks[1].rotation.times_seconds.push_back(float(k) / 3000.0f);
    dense.joint_tracks[1].rotation.values.push_back(test::axisAngleF(0.3 * std::sin(6.0 * k / 3000.0), {0, 0, 1}));
  }
  c.clips.push_back(dense);
  BakeDesc d;
  d.max_evaluations = 20000;  // About 800 frames of this character: the grid's 241 fit.
  d.accept_tolerance_miss = true;
  BakedPalette p;
  BakeReport r;
  const Status s = bakePalette(c, d, &p, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  EXPECT_FALSE(r.clips[0].frames_at_keys);
  EXPECT_TRUE(p.clips[0].frame_times_seconds.empty());
  d.placement = FramePlacement::kKeys;
  EXPECT_EQ(bakePalette(c, d, &p, &r).code(), StatusCode::kLimitExceeded);
}

// Half floats cannot reach 1e-4 of the height: the default bake fails by name, saying which
// clip and joint, the error reached and what was tried; accept_tolerance_miss keeps it.
TEST(ProductionClips, ATolerancePastTheFormatIsNamed) {
  Character c = test::chainCharacter(4);
  Clip swing = test::blankClip(c, "swing", 1.0f);
  swing.joint_tracks[1].rotation.times_seconds = {0.0f, 1.0f};
  swing.joint_tracks[1].rotation.values = {glm::quat(1, 0, 0, 0), test::axisAngleF(1.5, {0, 0, 1})};
  c.clips.push_back(swing);
  BakeDesc d;
  d.format = PaletteFormat::kMatrix3x4F16;
  BakedPalette p;
  p.character_height = -1.0f;  // Untouched on failure.
  BakeReport r;
  const Status s = bakePalette(c, d, &p, &r);
  ASSERT_EQ(s.code(), StatusCode::kToleranceNotMet) << s.toString();
  EXPECT_NE(s.message().find("clip 'swing'"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("joint "), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("matrix3x4_f16"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("240 Hz"), std::string::npos) << s.message();
  EXPECT_EQ(p.character_height, -1.0f);
  d.accept_tolerance_miss = true;
  ASSERT_TRUE(bakePalette(c, d, &p, &r).isOk());
  EXPECT_FALSE(r.clips[0].tolerance_met);
  // A fixed rate is the caller's choice: reported, not refused.
  d.accept_tolerance_miss = false;
  d.rate_mode = RateMode::kFixed;
  EXPECT_TRUE(bakePalette(c, d, &p, &r).isOk());
}

}  // namespace
}  // namespace si
