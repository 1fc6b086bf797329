// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Shared fixtures for core tests: tiny skeletons and clips with known closed-form poses.

#include <cmath>

#include <gtest/gtest.h>

#include "si/core/character.h"
#include "si/core/clip.h"
#include "si/core/default_character.h"
#include "si/core/skeleton.h"
#include "si/core/skinned_mesh.h"

namespace si::test {

/// Named float tolerances (ozz gtest_math_helper style).
inline constexpr double kExactTolerance = 1e-12;   // Double arithmetic on exact inputs.
inline constexpr double kFloatInputTolerance = 1e-6;  // Inputs rounded to float.

inline constexpr double kPi = 3.14159265358979323846;

/// One triangle weighted to joints 0 and 1 (the third vertex half each), one sub-mesh "body":
/// valid for a skeleton of two joints.
inline SkinnedMesh twoJointTriangle() {
  SkinnedMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.joints = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}};
  m.weights = {{1, 0, 0, 0}, {1, 0, 0, 0}, {0.5f, 0.5f, 0, 0}};
  m.indices = {0, 1, 2};
  m.sub_meshes = {SubMesh{"body", {IndexRange{0, 3}}, 0, {}}};
  return m;
}

/// A chain of `n` joints, each 1 unit above its parent along +Y, with matching inverse binds.
inline Skeleton chainSkeleton(size_t n) {
  Skeleton s;
  for (size_t i = 0; i < n; ++i) {
    s.joint_names.push_back("j" + std::to_string(i));
    s.parents.push_back(i == 0 ? Skeleton::kNoParent : static_cast<int32_t>(i - 1));
    Transform t;
    t.translation = i == 0 ? glm::vec3(0.0f) : glm::vec3(0, 1, 0);
    s.rest_pose.push_back(t);
    glm::mat4 ibm(1.0f);
    ibm[3] = glm::vec4(0, -float(i), 0, 1);
    s.inverse_bind_matrices.push_back(ibm);
  }
  return s;
}

/// An empty clip (no tracks) for `joint_count` joints.
inline Clip emptyClip(size_t joint_count, float duration = 1.0f) {
  Clip c;
  c.name = "test";
  c.duration_seconds = duration;
  c.joint_tracks.resize(joint_count);
  return c;
}

inline glm::quat axisAngleF(double angle, glm::dvec3 axis) {
  return glm::quat(float(std::cos(angle / 2)), float(axis.x * std::sin(angle / 2)),
                   float(axis.y * std::sin(angle / 2)), float(axis.z * std::sin(angle / 2)));
}

/// Angle between two rotations in radians (0 for q and -q).
inline double rotationAngle(const glm::dquat& a, const glm::dquat& b) {
  const double d = std::fabs(a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z);
  return 2.0 * std::acos(std::min(1.0, d));
}

/// The embedded character (si::makeDefaultCharacter, default desc); a failure fails the test.
inline Character embeddedCharacter() {
  Character c;
  EXPECT_TRUE(makeDefaultCharacter({}, &c).isOk());
  return c;
}

/// The embedded character with its travelling clips (DefaultCharacterDesc::moving_clips, marked
/// for root motion); a failure fails the test.
inline Character travellingCharacter() {
  DefaultCharacterDesc d;
  d.moving_clips = true;
  Character c;
  EXPECT_TRUE(makeDefaultCharacter(d, &c).isOk());
  return c;
}

}  // namespace si::test
