// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Morph target weights in the palette (issue "Any animated glTF becomes a crowd", part 1): each
// frame stores the weights at its time beside the joints; the shader's interpolation of them
// (si::emulateMorphWeights) and the bake's error report, which must see the morphs, are checked
// against the reference evaluated here at many times.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/test_helpers.h"
#include "si/bake/animation_baker.h"
#include "si/bake/palette_file.h"
#include "si/core/baked_palette.h"
#include "si/core/palette_file.h"
#include "si/core/reference_evaluator.h"
#include "si/core/shader_inputs.h"

namespace si {
namespace {

// Two joints (the second 1 above the first), the triangle weighted to them, joint 1 turning
// about Z; two targets: "lift" moves vertex 2 by 0.5 in z along a CUBICSPLINE curve with an
// overshoot, "slide" (5 targets in all, so the weights take two texels) holds its default.
Character morphCharacter(Interpolation interp = Interpolation::kCubicSpline) {
  Character c;
  c.name = "morph";
  c.skeleton = test::chainSkeleton(2);
  c.mesh = test::twoJointTriangle();
  c.mesh.morph_targets.resize(5);
  MorphTarget& lift = c.mesh.morph_targets[0];
  lift.name = "lift";
  lift.vertices = {2};
  lift.position_deltas = {{0, 0, 0.5f}};
  lift.normal_deltas = {{0, -0.5f, 0}};
  for (size_t t = 1; t < 5; ++t) {
    c.mesh.morph_targets[t].name = "slide" + std::to_string(t);
    c.mesh.morph_targets[t].vertices = {0, 1};
    c.mesh.morph_targets[t].position_deltas = {{0.1f * float(t), 0, 0}, {0, 0.05f, 0}};
    c.mesh.morph_targets[t].default_weight = 0.25f * float(t);
  }
  Clip clip = test::emptyClip(2, 2.0f);
  clip.name = "talk";
  clip.loop_mode = LoopMode::kOnce;
  QuatTrack& turn = clip.joint_tracks[1].rotation;
  turn.times_seconds = {0.0f, 2.0f};
  turn.values = {glm::quat(1, 0, 0, 0), glm::angleAxis(0.5f, glm::vec3(0, 0, 1))};
  MorphWeightTrack w;
  w.first_target = 0;
  w.target_count = 1;
  w.interpolation = interp;
  w.times_seconds = {0.0f, 1.0f, 2.0f};
  w.values = interp == Interpolation::kCubicSpline
                 ? std::vector<float>{0, 0, 3.0f, -2.0f, 1.0f, 0.5f, 4.0f, 0.2f, 0}
                 : std::vector<float>{0, 1.0f, 0.2f};
  clip.morph_tracks = {w};
  c.clips = {clip};
  return c;
}

// The largest |shader - reference| over `samples` times of the clip, the shader emulated from
// the palette (matrices and morph weights), the reference in double.
double measuredMaxError(const Character& c, const BakedPalette& p, int samples) {
  const BakedClip& bc = p.clips[0];
  const Clip& clip = c.clips[0];
  std::vector<glm::mat4> matrices(c.skeleton.jointCount());
  std::vector<float> weights(c.mesh.morph_targets.size());
  std::vector<double> exact_weights(c.mesh.morph_targets.size());
  std::vector<glm::vec3> shader(c.mesh.vertexCount());
  std::vector<glm::dvec3> exact(c.mesh.vertexCount());
  double worst = 0.0;
  for (int i = 0; i <= samples; ++i) {
    const double t = clip.duration_seconds * double(i) / samples;
    const FrameSample s = sampleFrames(bc, t);
    EXPECT_TRUE(emulateSkinningMatrices(p, 0, s, matrices).isOk());
    EXPECT_TRUE(emulateMorphWeights(p, p.layout.frameTexel(0, s.frame),
                                    p.layout.frameTexel(0, s.next_frame), s.fraction, s.mode,
                                    weights)
                    .isOk());
    EXPECT_TRUE(emulateSkinning(c.mesh, matrices, shader, {}, weights).isOk());
    ReferencePose pose;
    EXPECT_TRUE(evaluateLocalPose(c.skeleton, clip, t, &pose).isOk());
    EXPECT_TRUE(evaluateMorphWeights(c.mesh, clip, t, exact_weights).isOk());
    EXPECT_TRUE(skinVertices(c.mesh, pose.skinning, exact, {}, {}, exact_weights).isOk());
    for (size_t v = 0; v < exact.size(); ++v)
      worst = std::max(worst, glm::distance(glm::dvec3(shader[v]), exact[v]));
  }
  return worst;
}

TEST(MorphBake, EachFrameStoresTheWeightsAtItsTime) {
  const Character c = morphCharacter();
  BakedPalette p;
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = 10.0f;
  ASSERT_TRUE(bakePalette(c, d, &p, nullptr).isOk());
  EXPECT_EQ(p.layout.morph_target_count, 5u);
  // Two texels of weights after two joints of stride 4, padded to a whole stride.
  EXPECT_EQ(p.layout.morph_first_texel, 2u * 4u);
  EXPECT_EQ(p.layout.frame_stride_texels, 2u * 4u + 4u);
  std::vector<float> stored(5);
  std::vector<double> exact(5);
  const BakedClip& bc = p.clips[0];
  for (uint32_t f = 0; f < bc.frame_count; ++f) {
    const uint32_t texel = p.layout.frameTexel(0, f);
    ASSERT_TRUE(emulateMorphWeights(p, texel, texel, 0.0f, IntervalMode::kLinear, stored).isOk());
    ASSERT_TRUE(
        evaluateMorphWeights(c.mesh, c.clips[0], f * bc.frame_interval_seconds, exact).isOk());
    for (size_t k = 0; k < 5; ++k) EXPECT_NEAR(stored[k], exact[k], 1e-6) << "frame " << f;
  }
  EXPECT_EQ(emulateMorphWeights(p, 0, 0, 0.0f, IntervalMode::kLinear, Span<float>(stored.data(), 4))
                .code(),
            StatusCode::kCountMismatch);
}

TEST(MorphBake, TheErrorReportSeesTheMorphs) {
  // At 2 Hz the cubic weight curve is coarse: the report's largest error must be the morphed
  // vertex's, as measured here at 400 times (the report samples fewer times: at most ours).
  const Character c = morphCharacter();
  BakedPalette p;
  BakeReport r;
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = 2.0f;
  ASSERT_TRUE(bakePalette(c, d, &p, &r).isOk());
  const double ours = measuredMaxError(c, p, 400);
  ASSERT_GT(ours, 0.01);  // A visible error: the test means something.
  EXPECT_LE(r.clips[0].max_error_units, ours * (1.0 + 1e-5));
  EXPECT_GE(r.clips[0].max_error_units, 0.8 * ours);
  EXPECT_EQ(r.clips[0].max_error_vertex, 2u);
}

TEST(MorphBake, TheDefaultBakeMeetsTheToleranceWithTheMorphs) {
  for (Interpolation interp :
       {Interpolation::kLinear, Interpolation::kStep, Interpolation::kCubicSpline}) {
    SCOPED_TRACE(interpolationName(interp));
    const Character c = morphCharacter(interp);
    BakedPalette p;
    BakeReport r;
    ASSERT_TRUE(bakePalette(c, BakeDesc(), &p, &r).isOk());
    EXPECT_TRUE(r.clips[0].tolerance_met);
    const double height = c.height();
    EXPECT_LE(r.clips[0].max_error_ratio, 1e-4);
    // Checked here too, densely: within the tolerance (a little over for times between the
    // report's samples).
    EXPECT_LE(measuredMaxError(c, p, 2000), 1.5e-4 * height);
  }
}

TEST(MorphBake, TheWeightsTravelInThePaletteFile) {
  const Character c = morphCharacter();
  BakedPalette p, loaded;
  ASSERT_TRUE(bakePalette(c, BakeDesc(), &p, nullptr).isOk());
  std::vector<uint8_t> bytes;
  ASSERT_TRUE(savePalette(p, &bytes).isOk());
  ASSERT_TRUE(loadPalette(bytes, &loaded).isOk());
  EXPECT_EQ(loaded.layout.morph_target_count, 5u);
  EXPECT_EQ(loaded.texel_bytes, p.texel_bytes);
  EXPECT_EQ(loaded.layout.frame_stride_texels, p.layout.frame_stride_texels);
}

// `c` baked at a fixed `hz` (cubic or linear) and its vertex and morph streams.
void bakeWithStreams(const Character& c, float hz, bool cubic, BakedPalette* p, VertexStream* vs,
                     MorphStream* ms) {
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = hz;
  d.interpolation = cubic ? InterpolationChoice::kCubic : InterpolationChoice::kLinear;
  ASSERT_TRUE(bakePalette(c, d, p, nullptr).isOk());
  ASSERT_TRUE(buildVertexStream(c.mesh, *p, vs).isOk());
  ASSERT_TRUE(buildMorphStream(c.mesh, *p, 0, ms).isOk());
}

// The morph stream's run of vertex `v` (si::VertexStream's morph word): each entry's word.
std::vector<uint32_t> runWords(const VertexStream& vs, const MorphStream& ms, uint32_t v) {
  uint32_t word;
  std::memcpy(&word, vs.bytes.data() + size_t(v) * vs.stride_bytes + vs.morph_offset, 4);
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < (word & 511u); ++i)
    out.push_back(ms.texels[size_t((word >> 9) + i) * ms.texels_per_entry * 4]);
  return out;
}
float tailOf(uint32_t word) {
  const uint32_t bits = word & 0xFFFF0000u;
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

// Each vertex's run lists its targets by effect (|delta| x the largest |weight| the palette
// gives the target), largest first; each entry's tail bounds what it and the rest of the run
// move the vertex, rounded up by less than 1 % (a LOD level stops where the tail is within its
// cut, si::morphLodCuts).
TEST(MorphBake, TheStreamOrdersEachRunByEffectWithItsTail) {
  const Character c = morphCharacter(Interpolation::kLinear);
  BakedPalette p;
  VertexStream vs;
  MorphStream ms;
  bakeWithStreams(c, 10.0f, false, &p, &vs, &ms);
  // The largest |weight| of each target over the palette's frames, read as the shader reads.
  std::vector<double> bound(5, 0.0);
  std::vector<float> w(5);
  const BakedClip& bc = p.clips[0];
  for (uint32_t f = 0; f < bc.frame_count; ++f) {
    const uint32_t texel = p.layout.frameTexel(0, f);
    ASSERT_TRUE(emulateMorphWeights(p, texel, texel, 0.0f, IntervalMode::kLinear, w).isOk());
    for (size_t k = 0; k < 5; ++k) bound[k] = std::max(bound[k], double(std::fabs(w[k])));
  }
  for (uint32_t v = 0; v < 3; ++v) {
    SCOPED_TRACE(testing::Message() << "vertex " << v);
    struct Expected {
      uint32_t target;
      double effect;
    };
    std::vector<Expected> expected;
    for (uint32_t t = 0; t < 5; ++t) {
      const MorphTarget& target = c.mesh.morph_targets[t];
      for (size_t i = 0; i < target.vertices.size(); ++i)
        if (target.vertices[i] == v)
          expected.push_back({t, glm::length(glm::dvec3(target.position_deltas[i])) * bound[t]});
    }
    std::stable_sort(expected.begin(), expected.end(),
                     [](const Expected& a, const Expected& b) { return a.effect > b.effect; });
    const std::vector<uint32_t> words = runWords(vs, ms, v);
    ASSERT_EQ(words.size(), expected.size());
    for (size_t i = 0; i < words.size(); ++i) {
      EXPECT_EQ(words[i] & 0xFFFFu, expected[i].target) << "entry " << i;
      double rest = 0.0;
      for (size_t j = i; j < expected.size(); ++j) rest += expected[j].effect;
      EXPECT_GE(tailOf(words[i]), rest) << "entry " << i;
      EXPECT_LE(tailOf(words[i]), rest * (1.0 + 1.0 / 128.0)) << "entry " << i;
    }
  }
  // The slides' effects differ (0.025 t^2): the run is not left in target order.
  EXPECT_EQ(runWords(vs, ms, 0)[0] & 0xFFFFu, 4u);
}

// A cubic palette overshoots its frames between them: the tail bounds what the interpolated
// weight gives, at every time (Catmull-Rom's weights sum to at most 1.25 in absolute value).
TEST(MorphBake, TheTailBoundsCubicWeightsBetweenFrames) {
  const Character c = morphCharacter(Interpolation::kCubicSpline);
  BakedPalette p;
  VertexStream vs;
  MorphStream ms;
  bakeWithStreams(c, 2.0f, true, &p, &vs, &ms);
  const std::vector<uint32_t> lift = runWords(vs, ms, 2);  // Only "lift", delta 0.5, moves it.
  ASSERT_EQ(lift.size(), 1u);
  const BakedClip& bc = p.clips[0];
  std::vector<float> w(5);
  double largest = 0.0;
  for (int i = 0; i <= 2000; ++i) {
    const FrameSample s = sampleFrames(bc, c.clips[0].duration_seconds * i / 2000.0);
    ASSERT_TRUE(emulateMorphWeights(p, p.layout.frameTexel(0, s.frame),
                                    p.layout.frameTexel(0, s.next_frame), s.fraction, s.mode, w)
                    .isOk());
    largest = std::max(largest, 0.5 * std::fabs(double(w[0])));
  }
  EXPECT_GE(tailOf(lift[0]), largest);
  EXPECT_LE(tailOf(lift[0]), 1.3 * largest);  // A bound, not far above what is reached.
}

TEST(MorphBake, AWeightThatIsNotFiniteIsRefusedByName) {
  BakedPalette p;
  ASSERT_TRUE(bakePalette(morphCharacter(), BakeDesc(), &p, nullptr).isOk());
  const uint32_t texel = p.layout.morphTexel(0, 1, 4);
  const float nan = NAN;
  std::memcpy(p.texel_bytes.data() + size_t(texel) * 16, &nan, 4);
  const Status s = p.validate();
  EXPECT_EQ(s.code(), StatusCode::kNotFinite);
  EXPECT_NE(s.message().find("morph targets 4 to 4"), std::string::npos) << s.toString();
}

}  // namespace
}  // namespace si
