// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Morph targets in the data model and the reference: their checks, their weights over a clip
// (LINEAR, STEP, CUBICSPLINE, defaults, the loop's wrap) and their application before skinning,
// each against values worked out here.
#include <gtest/gtest.h>

#include "core/test_helpers.h"
#include "si/core/morph_target.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {

using test::chainSkeleton;
using test::emptyClip;
using test::twoJointTriangle;

// The triangle with two targets: "lift" moves vertex 2 up in z and tips its normal; "slide"
// moves vertices 0 and 1 along x.
SkinnedMesh morphTriangle() {
  SkinnedMesh m = twoJointTriangle();
  MorphTarget lift;
  lift.name = "lift";
  lift.vertices = {2};
  lift.position_deltas = {{0, 0, 1}};
  lift.normal_deltas = {{0, -1, 0}};
  MorphTarget slide;
  slide.name = "slide";
  slide.vertices = {0, 1};
  slide.position_deltas = {{0.5f, 0, 0}, {0.25f, 0, 0}};
  slide.default_weight = 0.5f;
  m.morph_targets = {lift, slide};
  return m;
}

TEST(MorphTargets, ValidTargetsPass) {
  EXPECT_TRUE(morphTriangle().validate(2).isOk());
}

TEST(MorphTargets, EachBrokenRuleIsNamed) {
  const auto broken = [](auto change) {
    SkinnedMesh m = morphTriangle();
    change(&m);
    return m.validate(2);
  };
  Status s = broken([](SkinnedMesh* m) { m->morph_targets[1].vertices = {1, 0}; });
  EXPECT_EQ(s.code(), StatusCode::kNotSorted);
  EXPECT_NE(s.message().find("morph target 1 'slide'"), std::string::npos) << s.toString();
  s = broken([](SkinnedMesh* m) { m->morph_targets[0].vertices = {3}; });
  EXPECT_EQ(s.code(), StatusCode::kOutOfRange);
  s = broken([](SkinnedMesh* m) { m->morph_targets[1].position_deltas.pop_back(); });
  EXPECT_EQ(s.code(), StatusCode::kCountMismatch);
  s = broken([](SkinnedMesh* m) { m->morph_targets[1].normal_deltas = {{0, 0, 0}}; });
  EXPECT_EQ(s.code(), StatusCode::kCountMismatch);
  s = broken([](SkinnedMesh* m) { m->morph_targets[0].tangent_deltas = {{1, 0, 0}}; });
  EXPECT_EQ(s.code(), StatusCode::kCountMismatch);  // The mesh has no tangents.
  EXPECT_NE(s.message().find("no tangents"), std::string::npos) << s.toString();
  s = broken([](SkinnedMesh* m) { m->morph_targets[0].position_deltas[0].y = NAN; });
  EXPECT_EQ(s.code(), StatusCode::kNotFinite);
  s = broken([](SkinnedMesh* m) { m->morph_targets[1].default_weight = INFINITY; });
  EXPECT_EQ(s.code(), StatusCode::kNotFinite);
  s = broken([](SkinnedMesh* m) { m->morph_targets.resize(kMaxMorphTargets + 1); });
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
}

TEST(MorphTargets, ApplyAddsWeightedDeltasAndRenormalizes) {
  const SkinnedMesh m = morphTriangle();
  std::vector<glm::dvec3> p(m.positions.begin(), m.positions.end());
  std::vector<glm::dvec3> n(m.normals.begin(), m.normals.end());
  const std::vector<double> w = {0.5, 2.0};
  ASSERT_TRUE(applyMorphTargets(m.morph_targets, w, p, n, {}).isOk());
  EXPECT_EQ(p[0], glm::dvec3(1.0, 0, 0));
  EXPECT_EQ(p[1], glm::dvec3(1.5, 0, 0));
  EXPECT_EQ(p[2], glm::dvec3(0, 1, 0.5));
  // (0, 0, 1) + 0.5 (0, -1, 0), normalized.
  EXPECT_NEAR(glm::distance(n[2], glm::normalize(glm::dvec3(0, -0.5, 1))), 0.0, 1e-15);
  EXPECT_EQ(n[0], glm::dvec3(0, 0, 1));
  // A normal the deltas cancel keeps its bind-pose direction.
  std::vector<glm::dvec3> q(m.positions.begin(), m.positions.end());
  std::vector<glm::dvec3> cancel(3, glm::dvec3(0, 0, 1));
  SkinnedMesh flat = m;
  flat.morph_targets[0].normal_deltas = {{0, 0, -1}};
  ASSERT_TRUE(
      applyMorphTargets(flat.morph_targets, std::vector<double>{1.0, 0.0}, q, cancel, {}).isOk());
  EXPECT_EQ(cancel[2], glm::dvec3(0, 0, 1));
  EXPECT_EQ(applyMorphTargets(m.morph_targets, std::vector<double>{1.0}, p, n, {}).code(),
            StatusCode::kCountMismatch);
}

TEST(MorphTargets, SkinVerticesMorphsBeforeSkinning) {
  SkinnedMesh m = morphTriangle();
  std::vector<glm::dmat4> skinning(2, glm::dmat4(1.0));
  skinning[1] = glm::dmat4(2.0);  // Joint 1 scales by 2 (w stays 1 after the division-free use).
  skinning[1][3] = glm::dvec4(0, 0, 0, 1);
  std::vector<glm::dvec3> out(3);
  ASSERT_TRUE(skinVertices(m, skinning, out, {}, {}, std::vector<double>{1.0, 1.0}).isOk());
  EXPECT_EQ(out[0], glm::dvec3(0.5, 0, 0));    // Joint 0: identity.
  EXPECT_EQ(out[1], glm::dvec3(2.5, 0, 0));    // Joint 1: 2 * (1.25, 0, 0).
  EXPECT_EQ(out[2], glm::dvec3(0, 1.5, 1.5));  // Half each: 1.5 * (0, 1, 1).
  // No weights: the defaults (lift 0, slide 0.5).
  ASSERT_TRUE(skinVertices(m, skinning, out, {}, {}).isOk());
  EXPECT_EQ(out[0], glm::dvec3(0.25, 0, 0));
  EXPECT_EQ(out[2], glm::dvec3(0, 1.5, 0));
  EXPECT_EQ(skinVertices(m, skinning, out, {}, {}, std::vector<double>{1.0}).code(),
            StatusCode::kCountMismatch);
  SkinnedMesh plain = twoJointTriangle();
  EXPECT_EQ(skinVertices(plain, skinning, out, {}, {}, std::vector<double>{1.0}).code(),
            StatusCode::kCountMismatch);
  m.morph_targets[0].vertices = {7};
  EXPECT_EQ(skinVertices(m, skinning, out, {}, {}).code(), StatusCode::kOutOfRange);
}

Clip morphClip(Interpolation interp) {
  Clip c = emptyClip(2, 2.0f);
  MorphWeightTrack t;
  t.first_target = 1;
  t.target_count = 1;
  t.interpolation = interp;
  t.times_seconds = {0.5f, 1.5f};
  if (interp == Interpolation::kCubicSpline)
    t.values = {9.0f, 0.0f, 2.0f, -1.0f, 1.0f, 9.0f};  // (in, value, out) per key.
  else
    t.values = {0.0f, 1.0f};
  c.morph_tracks = {t};
  return c;
}

TEST(MorphTargets, WeightsFollowTheTrackOrTheDefault) {
  const SkinnedMesh m = morphTriangle();
  std::vector<double> w(2);
  Clip linear = morphClip(Interpolation::kLinear);
  ASSERT_TRUE(evaluateMorphWeights(m, linear, 0.75, w).isOk());
  EXPECT_DOUBLE_EQ(w[0], 0.0);   // lift: no track, its default.
  EXPECT_DOUBLE_EQ(w[1], 0.25);  // A quarter of the way from 0 to 1.
  ASSERT_TRUE(evaluateMorphWeights(m, linear, 0.1, w).isOk());
  EXPECT_DOUBLE_EQ(w[1], 0.0);  // Before the first key: held.
  ASSERT_TRUE(evaluateMorphWeights(m, linear, 1.9, w).isOk());
  EXPECT_DOUBLE_EQ(w[1], 1.0);  // After the last: held.
  ASSERT_TRUE(evaluateMorphWeights(m, morphClip(Interpolation::kStep), 1.4, w).isOk());
  EXPECT_DOUBLE_EQ(w[1], 0.0);
  // Hermite from 0 (out-tangent 2 per second) to 1 (in-tangent -1), over 1 s, at u = 0.5.
  ASSERT_TRUE(evaluateMorphWeights(m, morphClip(Interpolation::kCubicSpline), 1.0, w).isOk());
  EXPECT_NEAR(w[1], 0.125 * 2.0 + 0.5 * 1.0 + (-0.125) * -1.0, 1e-12);
  // A loop that wraps interpolates from the last key into the first: 1.5 s to 2.5 s.
  linear.loop_mode = LoopMode::kLoop;
  linear.wrap_interpolates = true;
  ASSERT_TRUE(evaluateMorphWeights(m, linear, 1.75, w).isOk());
  EXPECT_DOUBLE_EQ(w[1], 0.75);
}

TEST(MorphTargets, WeightEvaluationRefusesBadInput) {
  const SkinnedMesh m = morphTriangle();
  const Clip c = morphClip(Interpolation::kLinear);
  std::vector<double> one(1), two(2, -7.0);
  EXPECT_EQ(evaluateMorphWeights(m, c, 0.5, one).code(), StatusCode::kCountMismatch);
  EXPECT_EQ(evaluateMorphWeights(m, c, NAN, two).code(), StatusCode::kNotFinite);
  SkinnedMesh one_target = m;
  one_target.morph_targets.pop_back();  // The track's target 1 is past it.
  EXPECT_EQ(evaluateMorphWeights(one_target, c, 0.5, one).code(), StatusCode::kOutOfRange);
  EXPECT_EQ(two[0], -7.0);  // Untouched.
}

TEST(MorphTargets, ClipValidationChecksMorphTracks) {
  const auto broken = [](auto change) {
    Clip c = morphClip(Interpolation::kLinear);
    change(&c);
    return c.validate(2, 2);
  };
  EXPECT_TRUE(broken([](Clip*) {}).isOk());
  EXPECT_EQ(broken([](Clip* c) { c->morph_tracks[0].target_count = 0; }).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(broken([](Clip* c) { c->morph_tracks[0].first_target = 2; }).code(),
            StatusCode::kOutOfRange);
  EXPECT_EQ(broken([](Clip* c) { c->morph_tracks.push_back(c->morph_tracks[0]); }).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(broken([](Clip* c) { c->morph_tracks[0].values.push_back(0.5f); }).code(),
            StatusCode::kCountMismatch);
  EXPECT_EQ(broken([](Clip* c) {
              c->morph_tracks[0].interpolation = Interpolation::kCubicSpline;
            }).code(),
            StatusCode::kCountMismatch);  // Three per key.
  EXPECT_EQ(broken([](Clip* c) { c->morph_tracks[0].values[1] = NAN; }).code(),
            StatusCode::kNotFinite);
  EXPECT_EQ(broken([](Clip* c) {
              c->morph_tracks[0].times_seconds = {1.0f, 0.5f};
            }).code(),
            StatusCode::kNotSorted);
  EXPECT_EQ(broken([](Clip* c) { c->morph_tracks[0].times_seconds[1] = 3.0f; }).code(),
            StatusCode::kOutOfRange);  // Past the duration.
  // The last key time counts the morph tracks.
  EXPECT_FLOAT_EQ(morphClip(Interpolation::kLinear).lastKeyTime(), 1.5f);
}

TEST(MorphTargets, ACharacterChecksItsClipsAgainstItsTargets) {
  Character c;
  c.skeleton = chainSkeleton(2);
  c.mesh = morphTriangle();
  c.clips = {morphClip(Interpolation::kLinear)};
  EXPECT_TRUE(c.validate().isOk());
  c.mesh.morph_targets.pop_back();
  EXPECT_EQ(c.validate().code(), StatusCode::kOutOfRange);
}

}  // namespace
}  // namespace si
