// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The camera: frustum planes under each depth convention (si::DepthConvention), reverse-Z with a
// finite and an infinite far plane, a camera made from an engine's own view and projection
// matrices, and the crowd's selection under each.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

#include "si/crowd/camera.h"

namespace si {
namespace {

// Whether camera-relative point `p` passes every plane as the crowd's culling tests them
// (dot + w >= 0, so a NaN plane passes nothing).
bool inside(const Camera& c, const glm::vec3& p) {
  for (const glm::vec4& plane : c.frustumPlanes())
    if (!(glm::dot(glm::vec3(plane), p) + plane.w >= 0.0f)) return false;
  return true;
}

// Points on the view axis of a camera at the origin looking along -z.
glm::vec3 ahead(float distance) { return glm::vec3(0.0f, 0.0f, -distance); }

TEST(Camera, FrustumPlanesFollowTheDepthConvention) {
  const float fov = 0.9f, near_plane = 0.5f, far_plane = 100.0f;
  Camera negative = Camera::lookAt({0, 0, 0}, {0, 0, -1}, glm::vec3(0, 1, 0), fov, 1.0f,
                                   near_plane, far_plane);
  Camera zero_to_one = negative;
  zero_to_one.depth = DepthConvention::kZeroToOne;
  zero_to_one.projection = glm::perspectiveRH_ZO(fov, 1.0f, near_plane, far_plane);
  const Camera reversed = Camera::lookAtReverseZ({0, 0, 0}, {0, 0, -1}, glm::vec3(0, 1, 0), fov,
                                                 1.0f, near_plane, far_plane);
  EXPECT_EQ(reversed.depth, DepthConvention::kReversedZeroToOne);
  const Camera* cameras[] = {&negative, &zero_to_one, &reversed};
  for (const Camera* c : cameras) {
    SCOPED_TRACE(depthConventionName(c->depth));
    EXPECT_FALSE(inside(*c, ahead(0.45f)));  // Before the near plane,
    EXPECT_TRUE(inside(*c, ahead(0.55f)));
    EXPECT_TRUE(inside(*c, ahead(99.0f)));
    EXPECT_FALSE(inside(*c, ahead(101.0f)));  // past the far one,
    EXPECT_FALSE(inside(*c, glm::vec3(10.0f, 0.0f, -5.0f)));  // beside,
    EXPECT_FALSE(inside(*c, ahead(-5.0f)));                   // behind.
  }
  // Read with the wrong convention, a zero-to-one projection's near plane is wrong: the points
  // between the eye and the near plane pass.
  Camera misread = zero_to_one;
  misread.depth = DepthConvention::kNegativeOneToOne;
  EXPECT_TRUE(inside(misread, ahead(0.3f)));
}

TEST(Camera, ReverseZMapsTheNearPlaneToOneAndFarToZero) {
  const float near_plane = 0.25f;
  const Camera finite = Camera::lookAtReverseZ({0, 0, 0}, {0, 0, -1}, glm::vec3(0, 1, 0), 1.0f,
                                               1.5f, near_plane, 1000.0f);
  const Camera infinite = Camera::lookAtReverseZ({0, 0, 0}, {0, 0, -1}, glm::vec3(0, 1, 0),
                                                 1.0f, 1.5f, near_plane);
  const auto depth = [](const Camera& c, float distance) {
    const glm::vec4 clip = c.viewProjection() * glm::vec4(ahead(distance), 1.0f);
    return clip.z / clip.w;
  };
  EXPECT_NEAR(depth(finite, near_plane), 1.0f, 1e-6f);
  EXPECT_NEAR(depth(finite, 1000.0f), 0.0f, 1e-6f);
  EXPECT_NEAR(depth(infinite, near_plane), 1.0f, 1e-6f);
  EXPECT_NEAR(depth(infinite, 100.0f), near_plane / 100.0f, 1e-9f);
  // The infinite camera's far plane lets every distance through, however far.
  EXPECT_TRUE(inside(infinite, ahead(1e7f)));
  EXPECT_FALSE(inside(finite, ahead(1001.0f)));
  EXPECT_FALSE(inside(infinite, ahead(0.2f)));
}

TEST(Camera, FromAnEnginesMatricesEqualsLookAt) {
  const glm::dvec3 eye(1.0e6 + 3.25, 7.5, -2.0e5), target(1.0e6, 1.0, -2.0e5 - 40.0);
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  const Camera expected = Camera::lookAt(eye, target, up, 0.8f, 1.6f, 0.1f, 300.0f);
  const glm::dmat4 view = glm::lookAt(eye, target, glm::dvec3(up));
  const Camera c = Camera::fromMatrices(view, glm::perspective(0.8f, 1.6f, 0.1f, 300.0f),
                                        DepthConvention::kNegativeOneToOne, 720.0f);
  EXPECT_LT(glm::length(c.position - eye), 1e-6);  // Far from the origin: kept in double.
  EXPECT_EQ(c.viewport_height_pixels, 720.0f);
  const glm::mat4 a = c.viewProjection(), b = expected.viewProjection();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(a[i][j], b[i][j], 1e-5f) << i << " " << j;
  const auto pa = c.frustumPlanes(), pb = expected.frustumPlanes();
  for (size_t k = 0; k < pa.size(); ++k)
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(pa[k][i], pb[k][i], 1e-4f) << k << " " << i;
}

TEST(Camera, FromAViewMatrixThatIsNotRigidCullsEverything) {
  const glm::mat4 projection = glm::perspective(0.8f, 1.0f, 0.1f, 300.0f);
  const glm::dmat4 rigid = glm::lookAt(glm::dvec3(0, 1, 5), glm::dvec3(0, 1, 0), glm::dvec3(0, 1, 0));
  EXPECT_TRUE(inside(Camera::fromMatrices(rigid, projection), glm::vec3(0.0f, 0.0f, -5.0f)));
  for (const glm::dmat4& bad :
       {glm::scale(rigid, glm::dvec3(2.0)), glm::dmat4(0.0), glm::dmat4(std::nan("")),
        glm::scale(rigid, glm::dvec3(1.0, 1.0, -1.0))}) {  // Scaled, zero, NaN, mirrored.
    const Camera c = Camera::fromMatrices(bad, projection);
    EXPECT_FALSE(inside(c, glm::vec3(0.0f, 0.0f, -5.0f)));
    EXPECT_FALSE(inside(c, glm::vec3(0.0f)));
  }
}

}  // namespace
}  // namespace si
