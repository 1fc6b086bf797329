// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// si::rigidBlend: the fraction of the rigid motion between two matrices, not their lerp.
#include "si/core/rigid_blend.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

namespace si {
namespace {

float maxDiff(const glm::mat4& a, const glm::mat4& b) {
  float m = 0.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m = std::max(m, std::abs(a[c][r] - b[c][r]));
  return m;
}

// A rotation by `degrees` about `axis` through `pivot`.
glm::mat4 turnAbout(const glm::vec3& pivot, const glm::vec3& axis, float degrees) {
  return glm::translate(glm::mat4(1.0f), pivot) *
         glm::rotate(glm::mat4(1.0f), glm::radians(degrees), glm::normalize(axis)) *
         glm::translate(glm::mat4(1.0f), -pivot);
}

TEST(RigidBlend, EndsAtBothMatrices) {
  const glm::mat4 a = glm::translate(glm::mat4(1.0f), {1, 2, 3}) * turnAbout({0, 1, 0}, {1, 1, 0}, 40);
  const glm::mat4 c = turnAbout({0.3f, 1.5f, -2}, {0, 0, 1}, 150) * glm::scale(glm::mat4(1.0f), glm::vec3(1.2f));
  EXPECT_LT(maxDiff(rigidBlend(a, c, 0.0f), a), 1e-5f);
  EXPECT_LT(maxDiff(rigidBlend(a, c, 1.0f), c), 2e-5f);
}

// An arm turned 150 degrees about its shoulder: half-way, the blend has turned it 75 degrees
// about the same shoulder (on the arc); the lerp pulls the hand in towards the shoulder.
TEST(RigidBlend, SwingsOnTheArcWhereTheLerpCollapses) {
  const glm::vec3 shoulder(0.2f, 1.5f, 0.0f), hand(0.9f, 1.5f, 0.0f);
  const glm::mat4 body = glm::translate(glm::mat4(1.0f), {3, 0, -1}) * turnAbout({}, {0, 1, 0}, 30);
  const glm::mat4 a = body, c = body * turnAbout(shoulder, {0, 0, 1}, 150);
  for (float t : {0.25f, 0.5f, 0.75f}) {
    const glm::vec3 expected = body * turnAbout(shoulder, {0, 0, 1}, 150 * t) * glm::vec4(hand, 1);
    const glm::vec3 blended = rigidBlend(a, c, t) * glm::vec4(hand, 1);
    const glm::vec3 lerped = (a * (1 - t) + c * t) * glm::vec4(hand, 1);
    EXPECT_LT(glm::distance(blended, expected), 1e-5f) << t;
    EXPECT_GT(glm::distance(lerped, expected), 0.05f) << t;  // What the blend replaces.
  }
}

// The same blend whatever common frame both matrices are expressed in.
TEST(RigidBlend, DoesNotDependOnTheCommonFrame) {
  const glm::mat4 a = turnAbout({0, 1, 0}, {1, 0, 0}, 20), c = turnAbout({0.5f, 1, 0}, {0, 1, 1}, 110);
  const glm::mat4 left = glm::translate(glm::mat4(1.0f), {4, -2, 7}) * turnAbout({}, {1, 2, 3}, 77) *
                         glm::scale(glm::mat4(1.0f), glm::vec3(0.5f));
  const glm::mat4 right = glm::inverse(turnAbout({1, 1, 1}, {0, 0, 1}, -35));  // An inverse bind.
  for (float t : {0.3f, 0.6f}) {
    const glm::mat4 in_frame = rigidBlend(left * a * right, left * c * right, t);
    EXPECT_LT(maxDiff(in_frame, left * rigidBlend(a, c, t) * right), 1e-4f) << t;
  }
}

TEST(RigidBlend, BlendsUniformScaleAndKeepsTheRest) {
  const glm::mat4 a(1.0f);
  EXPECT_LT(maxDiff(rigidBlend(a, glm::scale(a, glm::vec3(2.0f)), 0.5f), glm::scale(a, glm::vec3(1.5f))), 1e-5f);
  // Non-uniform scale is not rigid: the rest is added in proportion, so both ends hold.
  const glm::mat4 stretched = glm::scale(a, {1.0f, 2.0f, 1.0f});
  EXPECT_LT(maxDiff(rigidBlend(a, stretched, 1.0f), stretched), 1e-5f);
  const glm::mat4 half = rigidBlend(a, stretched, 0.5f);
  EXPECT_GT(half[1][1], 1.2f);
  EXPECT_LT(half[1][1], 1.8f);
  // A mirror cannot be reached by a rotation: the element-wise lerp.
  const glm::mat4 mirror = glm::scale(a, {-1.0f, 1.0f, 1.0f});
  EXPECT_LT(maxDiff(rigidBlend(a, mirror, 0.25f), a * 0.75f + mirror * 0.25f), 1e-6f);
}

}  // namespace
}  // namespace si
