// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The reference evaluator against closed-form cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/test_helpers.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {
using test::kPi;

Vec3Track vecTrack(Interpolation i, std::vector<float> times, std::vector<glm::vec3> values) {
  Vec3Track t;
  t.interpolation = i;
  t.times_seconds = std::move(times);
  t.values = std::move(values);
  return t;
}

TEST(ReferenceEvaluator, ConstantAngularSpeedSlerp) {
  QuatTrack t;
  t.times_seconds = {0.0f, 1.0f};
  t.values = {glm::quat(1, 0, 0, 0), test::axisAngleF(kPi / 2, {0, 0, 1})};
  for (double time : {0.0, 0.1, 0.25, 0.5, 0.9, 1.0}) {
    const glm::dquat q = sampleTrack(t, time);
    const glm::dquat expected(std::cos(time * kPi / 4), 0, 0, std::sin(time * kPi / 4));
    EXPECT_LT(test::rotationAngle(q, expected), test::kFloatInputTolerance) << "t=" << time;
  }
}

TEST(ReferenceEvaluator, AntipodalKeysTakeTheShortArc) {
  QuatTrack t;
  t.times_seconds = {0.0f, 1.0f};
  const glm::quat q90 = test::axisAngleF(kPi / 2, {0, 0, 1});
  t.values = {glm::quat(1, 0, 0, 0), -q90};  // Same rotation as q90, other hemisphere.
  const glm::dquat mid = sampleTrack(t, 0.5);
  const glm::dquat expected(std::cos(kPi / 8), 0, 0, std::sin(kPi / 8));  // 45 degrees.
  EXPECT_LT(test::rotationAngle(mid, expected), test::kFloatInputTolerance);
}

TEST(ReferenceEvaluator, NonUnitKeysAreNormalized) {
  QuatTrack t;
  t.times_seconds = {0.0f, 1.0f};
  t.values = {glm::quat(2, 0, 0, 0), test::axisAngleF(kPi / 2, {1, 0, 0}) * 0.5f};
  const glm::dquat q = sampleTrack(t, 0.5);
  EXPECT_NEAR(glm::length(q), 1.0, test::kExactTolerance);
  EXPECT_LT(test::rotationAngle(q, glm::dquat(std::cos(kPi / 8), std::sin(kPi / 8), 0, 0)),
            test::kFloatInputTolerance);
}

TEST(ReferenceEvaluator, StepHolds) {
  const Vec3Track t = vecTrack(Interpolation::kStep, {0, 1, 2}, {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
  EXPECT_EQ(sampleTrack(t, 0.999).x, 0.0);
  EXPECT_EQ(sampleTrack(t, 1.0).x, 1.0);
  EXPECT_EQ(sampleTrack(t, 1.5).x, 1.0);
  EXPECT_EQ(sampleTrack(t, 1.9999).x, 1.0);
  EXPECT_EQ(sampleTrack(t, 2.0).x, 2.0);
  EXPECT_EQ(sampleTrack(t, 7.0).x, 2.0);
}

TEST(ReferenceEvaluator, CubicSplineScalesTangentsByKeyInterval) {
  // Keys 2 s apart: with tangents scaled by the interval the midpoint is 1.0; unscaled, 0.75.
  const Vec3Track t = vecTrack(Interpolation::kCubicSpline, {0.0f, 2.0f},
                               {{0, 0, 0}, {0, 0, 0}, {1, 0, 0},     // in, value, out of key 0
                                {-1, 0, 0}, {1, 0, 0}, {0, 0, 0}});  // in, value, out of key 1
  EXPECT_NEAR(sampleTrack(t, 1.0).x, 1.0, test::kExactTolerance);
  EXPECT_EQ(sampleTrack(t, 0.0).x, 0.0);
  EXPECT_EQ(sampleTrack(t, 2.0).x, 1.0);
}

TEST(ReferenceEvaluator, CubicSplineReproducesACubic) {
  // f(t) = t^3 with tangents f'(t) = 3 t^2: Hermite interpolation is exact for cubics.
  std::vector<glm::vec3> v;
  for (float k : {0.0f, 1.0f, 2.0f})
    v.insert(v.end(), {{3 * k * k, 0, 0}, {k * k * k, 0, 0}, {3 * k * k, 0, 0}});
  const Vec3Track t = vecTrack(Interpolation::kCubicSpline, {0, 1, 2}, v);
  for (double time : {0.0, 0.3, 0.5, 1.0, 1.5, 1.75, 2.0})
    EXPECT_NEAR(sampleTrack(t, time).x, time * time * time, 1e-12) << "t=" << time;
}

TEST(ReferenceEvaluator, ClampsOutsideKeysAndSingleKey) {
  const Vec3Track t = vecTrack(Interpolation::kLinear, {0.5f, 1.5f}, {{1, 0, 0}, {3, 0, 0}});
  EXPECT_EQ(sampleTrack(t, 0.0).x, 1.0);
  EXPECT_EQ(sampleTrack(t, 1.0).x, 2.0);
  EXPECT_EQ(sampleTrack(t, 2.0).x, 3.0);
  const Vec3Track one = vecTrack(Interpolation::kLinear, {0.3f}, {{4, 5, 6}});
  EXPECT_EQ(sampleTrack(one, 0.0), glm::dvec3(4, 5, 6));
  EXPECT_EQ(sampleTrack(one, 9.0), glm::dvec3(4, 5, 6));
}

TEST(ReferenceEvaluator, ClipLocalTimeClampsAndLoops) {
  Clip once = test::emptyClip(1, 2.0f);
  Clip loop = once;
  loop.loop_mode = LoopMode::kLoop;
  EXPECT_EQ(clipLocalTime(once, 2.0), 2.0);  // Exactly at the end: the end.
  EXPECT_EQ(clipLocalTime(once, 5.0), 2.0);
  EXPECT_EQ(clipLocalTime(once, -1.0), 0.0);
  EXPECT_EQ(clipLocalTime(loop, 2.0), 0.0);  // Exactly at the end of a loop: the start.
  EXPECT_NEAR(clipLocalTime(loop, 4.5), 0.5, test::kExactTolerance);
  EXPECT_NEAR(clipLocalTime(loop, -0.5), 1.5, test::kExactTolerance);
  EXPECT_EQ(clipLocalTime(loop, 3.0, TimeWrap::kClamp), 2.0);
  EXPECT_NEAR(clipLocalTime(once, 3.0, TimeWrap::kLoop), 1.0, test::kExactTolerance);
  Clip zero = test::emptyClip(1, 0.0f);
  zero.loop_mode = LoopMode::kLoop;
  EXPECT_EQ(clipLocalTime(zero, 12.0), 0.0);
}

TEST(ReferenceEvaluator, WrapInterpolationOnlyWhenTheClipSaysSo) {
  Clip c = test::emptyClip(1, 1.0f);
  c.loop_mode = LoopMode::kLoop;
  c.joint_tracks[0].translation =
      vecTrack(Interpolation::kLinear, {0.0f, 0.5f}, {{0, 0, 0}, {1, 0, 0}});
  const Skeleton s = test::chainSkeleton(1);
  ReferencePose pose;
  ASSERT_TRUE(evaluatePose(s, c, 0.75, &pose).isOk());
  EXPECT_EQ(pose.local[0].translation.x, 1.0);  // Holds the last key.
  c.wrap_interpolates = true;
  ASSERT_TRUE(evaluatePose(s, c, 0.75, &pose).isOk());
  EXPECT_NEAR(pose.local[0].translation.x, 0.5, test::kExactTolerance);  // Half way back.
  ASSERT_TRUE(evaluatePose(s, c, 1.75, &pose).isOk());
  EXPECT_NEAR(pose.local[0].translation.x, 0.5, test::kExactTolerance);
}

TEST(ReferenceEvaluator, EvaluatePoseComposesHierarchy) {
  const Skeleton s = test::chainSkeleton(3);
  Clip c = test::emptyClip(3, 1.0f);
  c.joint_tracks[0].rotation.times_seconds = {0.0f};
  c.joint_tracks[0].rotation.values = {test::axisAngleF(kPi / 2, {0, 0, 1})};
  ReferencePose pose;
  ASSERT_TRUE(evaluatePose(s, c, 0.0, &pose).isOk());
  // Joint 1 (1 up) and 2 (2 up) rotate 90 degrees about Z around the root: to -X.
  EXPECT_NEAR(pose.model[1][3].x, -1.0, test::kFloatInputTolerance);
  EXPECT_NEAR(pose.model[2][3].x, -2.0, test::kFloatInputTolerance);
  EXPECT_NEAR(pose.model[2][3].y, 0.0, test::kFloatInputTolerance);
}

TEST(ReferenceEvaluator, EvaluatePoseRejectsBadInput) {
  const Skeleton s = test::chainSkeleton(2);
  Clip c = test::emptyClip(2);
  ReferencePose pose;
  EXPECT_EQ(evaluatePose(s, c, 0.0, nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(evaluatePose(s, c, std::numeric_limits<double>::quiet_NaN(), &pose).code(),
            StatusCode::kNotFinite);
  EXPECT_EQ(evaluatePose(s, test::emptyClip(3), 0.0, &pose).code(), StatusCode::kCountMismatch);
  EXPECT_TRUE(pose.local.empty());  // Untouched on failure.
}

TEST(ReferenceEvaluator, RestPoseSkinningIsIdentity) {
  const Skeleton s = test::chainSkeleton(4);
  ReferencePose pose;
  ASSERT_TRUE(evaluateRestPose(s, &pose).isOk());
  for (const glm::dmat4& m : pose.skinning)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(m[c][r], c == r ? 1.0 : 0.0, 1e-12);
}

// --- CPU skinning against hand-computed vertices -----------------------------------------

struct SkinFixture {
  Skeleton skeleton = test::chainSkeleton(2);
  SkinnedMesh mesh;
  SkinFixture() {
    mesh.positions = {{1, 1, 0}};
    mesh.normals = {{1, 0, 0}};
    mesh.tangents = {{0, 1, 0, -1}};
    mesh.joints = {{0, 1, 0, 0}};
    mesh.weights = {{0.5f, 0.5f, 0, 0}};
  }
};

TEST(SkinVertices, BlendsTwoJoints) {
  SkinFixture f;
  Clip c = test::emptyClip(2);
  c.joint_tracks[1].rotation.times_seconds = {0.0f};
  c.joint_tracks[1].rotation.values = {test::axisAngleF(kPi / 2, {0, 0, 1})};
  ReferencePose pose;
  ASSERT_TRUE(evaluatePose(f.skeleton, c, 0.0, &pose).isOk());
  glm::dvec3 p, n;
  glm::dvec4 t;
  ASSERT_TRUE(skinVertices(f.mesh, pose.skinning, Span<glm::dvec3>(&p, 1),
                           Span<glm::dvec3>(&n, 1), Span<glm::dvec4>(&t, 1)).isOk());
  // Joint 1 (at y=1) turns (1,1,0) into (0,2,0); half of each: (0.5, 1.5, 0).
  EXPECT_NEAR(p.x, 0.5, test::kFloatInputTolerance);
  EXPECT_NEAR(p.y, 1.5, test::kFloatInputTolerance);
  EXPECT_NEAR(p.z, 0.0, test::kFloatInputTolerance);
  // Normal (1,0,0) -> (1,0,0) and (0,1,0): blended and normalized.
  EXPECT_NEAR(n.x, std::sqrt(0.5), test::kFloatInputTolerance);
  EXPECT_NEAR(n.y, std::sqrt(0.5), test::kFloatInputTolerance);
  // Tangent (0,1,0) -> (0,1,0) and (-1,0,0); w kept.
  EXPECT_NEAR(t.x, -std::sqrt(0.5), test::kFloatInputTolerance);
  EXPECT_NEAR(t.y, std::sqrt(0.5), test::kFloatInputTolerance);
  EXPECT_EQ(t.w, -1.0);
}

glm::dvec3 skinnedNormal(glm::vec3 scale, glm::vec3 normal) {
  SkinFixture f;
  f.mesh.weights = {{1, 0, 0, 0}};
  f.mesh.normals = {normal};
  f.skeleton.rest_pose[0].scale = scale;
  ReferencePose pose;
  EXPECT_TRUE(evaluateRestPose(f.skeleton, &pose).isOk());
  glm::dvec3 p, n;
  EXPECT_TRUE(
      skinVertices(f.mesh, pose.skinning, Span<glm::dvec3>(&p, 1), Span<glm::dvec3>(&n, 1), {})
          .isOk());
  EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  return n;
}

TEST(SkinVertices, NormalsUseInverseTransposeForNonUniformScale) {
  const glm::dvec3 n = skinnedNormal({2, 1, 1}, glm::normalize(glm::vec3(1, 1, 0)));
  const glm::dvec3 expected = glm::normalize(glm::dvec3(0.5, 1, 0));
  EXPECT_NEAR(glm::length(n - expected), 0.0, test::kFloatInputTolerance);
}

TEST(SkinVertices, NormalsStayOutwardUnderMirroring) {
  const glm::dvec3 n = skinnedNormal({-1, 1, 1}, {1, 0, 0});
  EXPECT_NEAR(n.x, -1.0, test::kExactTolerance);
}

TEST(SkinVertices, ZeroScaleGivesFiniteNormals) {
  const glm::dvec3 degenerate = skinnedNormal({0, 1, 1}, {0, 1, 0});
  EXPECT_EQ(degenerate, glm::dvec3(0, 1, 0));  // Degenerate: bind-pose normal, documented.
  const glm::dvec3 along = skinnedNormal({0, 1, 1}, {1, 0, 0});
  EXPECT_NEAR(along.x, 1.0, test::kExactTolerance);
}

TEST(SkinVertices, RejectsWrongSizesAndJointIndices) {
  SkinFixture f;
  std::vector<glm::dmat4> one(1, glm::dmat4(1.0));
  std::vector<glm::dvec3> p(1), wrong(2);
  EXPECT_EQ(skinVertices(f.mesh, one, p, {}, {}).code(), StatusCode::kOutOfRange);
  std::vector<glm::dmat4> two(2, glm::dmat4(1.0));
  EXPECT_EQ(skinVertices(f.mesh, two, wrong, {}, {}).code(), StatusCode::kCountMismatch);
  EXPECT_TRUE(skinVertices(f.mesh, two, p, {}, {}).isOk());
  EXPECT_NEAR(p[0].x, 1.0, 1e-12);
}

}  // namespace
}  // namespace si
