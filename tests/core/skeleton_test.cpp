// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include <limits>

#include "core/test_helpers.h"
#include "si/core/skeleton.h"

namespace si {
namespace {

TEST(Skeleton, ValidityMatrix) {
  EXPECT_EQ(Skeleton().validate().code(), StatusCode::kLimitExceeded);  // Default fails.
  EXPECT_TRUE(test::chainSkeleton(1).validate().isOk());                 // Minimal passes.
  EXPECT_TRUE(test::chainSkeleton(5).validate().isOk());

  Skeleton s = test::chainSkeleton(3);
  s.joint_names.pop_back();
  EXPECT_EQ(s.validate().code(), StatusCode::kCountMismatch);
  s = test::chainSkeleton(3);
  s.rest_pose.pop_back();
  EXPECT_EQ(s.validate().code(), StatusCode::kCountMismatch);
  s = test::chainSkeleton(3);
  s.inverse_bind_matrices.push_back(glm::mat4(1.0f));
  EXPECT_EQ(s.validate().code(), StatusCode::kCountMismatch);

  s = test::chainSkeleton(3);
  s.parents[1] = 2;  // Child before parent.
  EXPECT_EQ(s.validate().code(), StatusCode::kNotSorted);
  s.parents[1] = 1;  // Self parent.
  EXPECT_EQ(s.validate().code(), StatusCode::kNotSorted);
  s.parents[1] = -2;
  EXPECT_EQ(s.validate().code(), StatusCode::kOutOfRange);

  s = test::chainSkeleton(3);
  s.rest_pose[2].translation.x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(s.validate().code(), StatusCode::kNotFinite);
  s = test::chainSkeleton(3);
  s.rest_pose[2].scale.y = std::numeric_limits<float>::infinity();
  EXPECT_EQ(s.validate().code(), StatusCode::kNotFinite);
  s = test::chainSkeleton(3);
  s.inverse_bind_matrices[1][2][2] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(s.validate().code(), StatusCode::kNotFinite);
  s = test::chainSkeleton(3);
  s.rest_pose[0].rotation = glm::quat(0, 0, 0, 0);
  EXPECT_EQ(s.validate().code(), StatusCode::kInvalidArgument);
}

TEST(Skeleton, MessageNamesJoint) {
  Skeleton s = test::chainSkeleton(3);
  s.rest_pose[2].translation.x = std::numeric_limits<float>::quiet_NaN();
  const Status st = s.validate();
  EXPECT_NE(st.message().find("joint 2 'j2'"), std::string::npos) << st.message();
}

TEST(Skeleton, SeveralRootsAndNegativeScaleAreValid) {
  Skeleton s = test::chainSkeleton(3);
  s.parents[2] = Skeleton::kNoParent;
  s.rest_pose[1].scale = glm::vec3(-1, 1, 0);  // Mirror and zero scale are representable.
  EXPECT_TRUE(s.validate().isOk());
}

TEST(Skeleton, FindJoint) {
  const Skeleton s = test::chainSkeleton(3);
  EXPECT_EQ(s.findJoint("j1"), 1);
  EXPECT_EQ(s.findJoint("nope"), -1);
}

}  // namespace
}  // namespace si
