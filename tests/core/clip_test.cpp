// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include <limits>

#include "core/test_helpers.h"
#include "si/core/clip.h"

namespace si {
namespace {

Clip validClip() {
  Clip c = test::emptyClip(2, 2.0f);
  c.joint_tracks[1].translation.times_seconds = {0.0f, 1.0f, 2.0f};
  c.joint_tracks[1].translation.values = {glm::vec3(0), glm::vec3(1), glm::vec3(2)};
  c.joint_tracks[0].rotation.interpolation = Interpolation::kCubicSpline;
  c.joint_tracks[0].rotation.times_seconds = {0.5f, 1.5f};
  c.joint_tracks[0].rotation.values = {glm::quat(0, 0, 0, 0), glm::quat(1, 0, 0, 0),
                                       glm::quat(0, 0, 0, 0), glm::quat(0, 0, 0, 0),
                                       glm::quat(1, 0, 0, 0), glm::quat(0, 0, 0, 0)};
  return c;
}

TEST(Clip, ValidityMatrix) {
  EXPECT_TRUE(test::emptyClip(2).validate(2).isOk());
  EXPECT_TRUE(validClip().validate(2).isOk());
  EXPECT_EQ(validClip().validate(3).code(), StatusCode::kCountMismatch);

  Clip c = validClip();
  c.duration_seconds = -1.0f;
  EXPECT_EQ(c.validate(2).code(), StatusCode::kOutOfRange);
  c.duration_seconds = std::numeric_limits<float>::infinity();
  EXPECT_EQ(c.validate(2).code(), StatusCode::kNotFinite);
  c = validClip();
  c.duration_seconds = 1.0f;  // Keys after the end.
  EXPECT_EQ(c.validate(2).code(), StatusCode::kOutOfRange);

  c = validClip();
  c.joint_tracks[1].translation.times_seconds[2] = 1.0f;  // Not strictly increasing.
  EXPECT_EQ(c.validate(2).code(), StatusCode::kNotSorted);
  c = validClip();
  c.joint_tracks[1].translation.times_seconds[0] = -0.5f;
  EXPECT_EQ(c.validate(2).code(), StatusCode::kOutOfRange);
  c = validClip();
  c.joint_tracks[1].translation.times_seconds[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(c.validate(2).code(), StatusCode::kNotFinite);
  c = validClip();
  c.joint_tracks[1].translation.values.pop_back();
  EXPECT_EQ(c.validate(2).code(), StatusCode::kCountMismatch);
  c = validClip();
  c.joint_tracks[0].rotation.values.pop_back();  // CUBICSPLINE needs 3 per key.
  EXPECT_EQ(c.validate(2).code(), StatusCode::kCountMismatch);
  c = validClip();
  c.joint_tracks[1].translation.values[1].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(c.validate(2).code(), StatusCode::kNotFinite);
  c = validClip();
  c.joint_tracks[0].rotation.values[1] = glm::quat(0, 0, 0, 0);  // Zero-length key value.
  EXPECT_EQ(c.validate(2).code(), StatusCode::kInvalidArgument);
  c = validClip();
  c.joint_tracks[0].rotation.interpolation = static_cast<Interpolation>(9);
  EXPECT_EQ(c.validate(2).code(), StatusCode::kInvalidArgument);
  c = validClip();
  c.loop_mode = static_cast<LoopMode>(7);
  EXPECT_EQ(c.validate(2).code(), StatusCode::kInvalidArgument);

  // Markers: within [0, duration], finite, named.
  c = validClip();
  c.markers = {{0.0, "start"}, {double(c.duration_seconds), "end"}};
  EXPECT_TRUE(c.validate(2).isOk());
  c.markers.push_back({double(c.duration_seconds) + 1e-3, "late"});
  const Status late = c.validate(2);
  EXPECT_EQ(late.code(), StatusCode::kOutOfRange);
  EXPECT_NE(late.message().find("marker 2 'late'"), std::string::npos) << late.message();
  c.markers.back() = {-0.1, "early"};
  EXPECT_EQ(c.validate(2).code(), StatusCode::kOutOfRange);
  c.markers.back() = {std::numeric_limits<double>::quiet_NaN(), "nan"};
  EXPECT_EQ(c.validate(2).code(), StatusCode::kNotFinite);
  c.markers.back() = {0.1, ""};
  EXPECT_EQ(c.validate(2).code(), StatusCode::kInvalidArgument);
}

TEST(Clip, MessageNamesClipJointAndProperty) {
  Clip c = validClip();
  c.name = "run";
  c.joint_tracks[1].translation.times_seconds[2] = 1.0f;
  const Status s = c.validate(2);
  EXPECT_NE(s.message().find("clip 'run': joint 1 translation"), std::string::npos)
      << s.message();
}

TEST(Clip, LastKeyTimeAndDefaults) {
  EXPECT_FLOAT_EQ(validClip().lastKeyTime(), 2.0f);
  EXPECT_FLOAT_EQ(test::emptyClip(3).lastKeyTime(), 0.0f);
  EXPECT_EQ(resolveInterpolation(Interpolation::kDefault), Interpolation::kLinear);
  EXPECT_EQ(resolveLoopMode(LoopMode::kDefault), LoopMode::kOnce);
  EXPECT_STREQ(interpolationName(Interpolation::kCubicSpline), "CUBICSPLINE");
}

}  // namespace
}  // namespace si
