// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// si::localBlend: a joint's transform relative to its parent, seen through the bind matrices,
// blended as the reference blends the local transform.
#include "si/core/local_blend.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

namespace si {
namespace {

float maxDiff(const glm::mat4& a, const glm::mat4& b) {
  float m = 0.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m = std::max(m, std::abs(a[c][r] - b[c][r]));
  return m;
}

struct Local {
  glm::vec3 translation;
  glm::quat rotation;
  float scale;
  glm::mat4 matrix() const {
    return glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) *
           glm::scale(glm::mat4(1.0f), glm::vec3(scale));
  }
};

// The reference's blend of local transforms: translation and scale lerped, rotation slerped
// along the shorter arc.
glm::mat4 referenceBlend(const Local& a, const Local& c, float t) {
  glm::quat qc = c.rotation;
  if (glm::dot(a.rotation, qc) < 0.0f) qc = -qc;
  return Local{glm::mix(a.translation, c.translation, t), glm::slerp(a.rotation, qc, t),
               a.scale + (c.scale - a.scale) * t}
      .matrix();
}

// Bind matrices (a rotation, a translation and a uniform scale) of a parent and its joint.
const glm::mat4 kBindParent = glm::translate(glm::mat4(1.0f), {0.3f, 1.4f, -0.2f}) *
                              glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(1, 2, 3))) *
                              glm::scale(glm::mat4(1.0f), glm::vec3(0.01f));
const glm::mat4 kBindJoint = glm::translate(glm::mat4(1.0f), {0.6f, 1.5f, -0.1f}) *
                             glm::rotate(glm::mat4(1.0f), -1.1f, glm::normalize(glm::vec3(0, 1, 1))) *
                             glm::scale(glm::mat4(1.0f), glm::vec3(0.01f));

// What the palette gives for the joint relative to its parent: bind_parent * local * inverse(bind_joint).
glm::mat4 seenThroughBinds(const glm::mat4& local) { return kBindParent * local * glm::inverse(kBindJoint); }

// The property the layered blend rests on: blending the palette's relative transforms is
// blending the local transforms, whatever the bind matrices, for turns up to 170 degrees apart.
TEST(LocalBlend, IsTheReferencesLocalBlendSeenThroughTheBinds) {
  const glm::vec3 pivot(kBindJoint[3]);
  const Local a{{0.0f, 30.0f, 2.0f}, glm::angleAxis(0.4f, glm::normalize(glm::vec3(1, 0, 1))), 1.0f};
  for (float degrees : {10.0f, 90.0f, 139.0f, 170.0f}) {
    const Local c{{5.0f, 28.0f, -1.0f},
                  a.rotation * glm::angleAxis(glm::radians(degrees), glm::normalize(glm::vec3(0, 1, 2))), 1.3f};
    for (float t : {0.0f, 0.25f, 0.5f, 0.8f, 1.0f}) {
      const glm::mat4 blended =
          localBlend(seenThroughBinds(a.matrix()), seenThroughBinds(c.matrix()), pivot, t);
      EXPECT_LT(maxDiff(blended, seenThroughBinds(referenceBlend(a, c, t))), 2e-5f) << degrees << " " << t;
    }
  }
}

// An arm turned 150 degrees about its shoulder: half-way the blend has turned it 75 degrees
// about the same shoulder (the joint's bind origin, given as the pivot); the lerp pulls the hand
// in towards the shoulder, and another pivot swings it on another arc.
TEST(LocalBlend, TurnsAboutTheJointsOrigin) {
  const glm::vec3 shoulder(0.2f, 1.5f, 0.0f), hand(0.9f, 1.5f, 0.0f);
  const auto turn = [&](float degrees) {
    return glm::translate(glm::mat4(1.0f), shoulder) *
           glm::rotate(glm::mat4(1.0f), glm::radians(degrees), {0, 0, 1}) *
           glm::translate(glm::mat4(1.0f), -shoulder);
  };
  const glm::mat4 a(1.0f), c = turn(150);
  for (float t : {0.25f, 0.5f, 0.75f}) {
    const glm::vec3 expected = turn(150 * t) * glm::vec4(hand, 1);
    EXPECT_LT(glm::distance(glm::vec3(localBlend(a, c, shoulder, t) * glm::vec4(hand, 1)), expected), 1e-5f);
    EXPECT_GT(glm::distance(glm::vec3((a * (1 - t) + c * t) * glm::vec4(hand, 1)), expected), 0.05f);
    EXPECT_GT(glm::distance(glm::vec3(localBlend(a, c, hand, t) * glm::vec4(hand, 1)), expected), 0.05f);
  }
}

// Each joint turns the shorter way (the reference's slerp does): 200 degrees is -160.
TEST(LocalBlend, TakesTheShorterArc) {
  const glm::mat4 a(1.0f), c = glm::rotate(glm::mat4(1.0f), glm::radians(200.0f), {0, 0, 1});
  const glm::mat4 half = localBlend(a, c, glm::vec3(0.0f), 0.5f);
  EXPECT_NEAR(glm::degrees(std::atan2(half[0][1], half[0][0])), -80.0f, 1e-3f);
}

TEST(LocalBlend, BlendsUniformScaleAndKeepsTheRest) {
  const glm::mat4 a(1.0f);
  const glm::vec3 o(0.0f);
  EXPECT_LT(maxDiff(localBlend(a, glm::scale(a, glm::vec3(2.0f)), o, 0.5f), glm::scale(a, glm::vec3(1.5f))), 1e-5f);
  // Non-uniform scale is not a rotation and uniform scale: the rest is lerped, both ends hold.
  const glm::mat4 stretched = glm::scale(a, {1.0f, 2.0f, 1.0f});
  EXPECT_LT(maxDiff(localBlend(a, stretched, o, 1.0f), stretched), 1e-5f);
  const glm::mat4 half = localBlend(a, stretched, o, 0.5f);
  EXPECT_GT(half[1][1], 1.2f);
  EXPECT_LT(half[1][1], 1.8f);
  // A mirror cannot be reached by a rotation: the element-wise lerp.
  const glm::mat4 mirror = glm::scale(a, {-1.0f, 1.0f, 1.0f});
  EXPECT_LT(maxDiff(localBlend(a, mirror, o, 0.25f), a * 0.75f + mirror * 0.25f), 1e-6f);
}

TEST(LocalBlend, AffineInverseUndoesTheMatrix) {
  const glm::mat4 m = kBindParent * glm::translate(glm::mat4(1.0f), {1, 2, 3});
  EXPECT_LT(maxDiff(affineInverse(m) * m, glm::mat4(1.0f)), 1e-4f);
}

}  // namespace
}  // namespace si
