// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include <limits>

#include "core/test_helpers.h"
#include "si/core/skinned_mesh.h"

namespace si {
namespace {

SkinnedMesh triangle() {
  return test::twoJointTriangle();
}

TEST(SkinnedMesh, ValidityMatrix) {
  EXPECT_EQ(SkinnedMesh().validate(2).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(triangle().validate(2).isOk());
  EXPECT_EQ(triangle().validate(1).code(), StatusCode::kOutOfRange);  // Joint 1 of 1.

  SkinnedMesh m = triangle();
  m.normals.pop_back();
  EXPECT_EQ(m.validate(2).code(), StatusCode::kCountMismatch);
  m = triangle();
  m.tangents = {glm::vec4(1, 0, 0, 1)};
  EXPECT_EQ(m.validate(2).code(), StatusCode::kCountMismatch);
  m = triangle();
  m.texcoords.resize(3);
  EXPECT_TRUE(m.validate(2).isOk());
  m = triangle();
  m.positions[1].x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(m.validate(2).code(), StatusCode::kNotFinite);
  m = triangle();
  m.weights[2] = glm::vec4(1.2f, -0.2f, 0, 0);
  EXPECT_EQ(m.validate(2).code(), StatusCode::kOutOfRange);
  m = triangle();
  m.weights[2] = glm::vec4(0.49f, 0.49f, 0, 0);  // Sum 0.98.
  EXPECT_EQ(m.validate(2).code(), StatusCode::kInvalidArgument);
  m = triangle();
  m.indices.push_back(0);
  EXPECT_EQ(m.validate(2).code(), StatusCode::kInvalidArgument);
  m = triangle();
  m.indices[2] = 3;
  EXPECT_EQ(m.validate(2).code(), StatusCode::kOutOfRange);
  m = triangle();
  m.sub_meshes.clear();
  EXPECT_EQ(m.validate(2).code(), StatusCode::kLimitExceeded);
  m = triangle();
  m.sub_meshes.resize(SkinnedMesh::kMaxSubMeshes + 1, m.sub_meshes[0]);
  EXPECT_EQ(m.validate(2).code(), StatusCode::kLimitExceeded);
  m = triangle();
  m.sub_meshes[0].lods.clear();
  EXPECT_EQ(m.validate(2).code(), StatusCode::kOutOfRange);
  m = triangle();
  m.sub_meshes[0].lods[0] = IndexRange{0, 6};  // Past the indices.
  EXPECT_EQ(m.validate(2).code(), StatusCode::kOutOfRange);
  m.sub_meshes[0].lods[0] = IndexRange{0, 0};  // Empty.
  EXPECT_EQ(m.validate(2).code(), StatusCode::kOutOfRange);
  m.sub_meshes[0].lods[0] = IndexRange{0xFFFFFFFDu, 6};  // Overflow-safe check.
  EXPECT_EQ(m.validate(2).code(), StatusCode::kOutOfRange);
}

TEST(SkinnedMesh, NormalizeWeightsRenormalizesAndReports) {
  SkinnedMesh m = triangle();
  m.weights[2] = glm::vec4(0.49f, 0.49f, 0, 0);
  WeightNormalizationReport r;
  ASSERT_TRUE(normalizeWeights(m, &r).isOk());
  EXPECT_EQ(r.vertices_changed, 1u);
  EXPECT_EQ(r.max_correction_vertex, 2u);
  EXPECT_NEAR(r.max_correction, 0.02f, 1e-6f);
  EXPECT_NEAR(m.weights[2].x, 0.5f, 1e-7f);
  EXPECT_TRUE(m.validate(2).isOk());
}

TEST(SkinnedMesh, NormalizeWeightsRejectsZeroSumWithoutTouchingMesh) {
  SkinnedMesh m = triangle();
  m.weights[0] = glm::vec4(0.9f, 0, 0, 0);
  m.weights[2] = glm::vec4(0.0f);
  EXPECT_EQ(normalizeWeights(m, nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(m.weights[0].x, 0.9f);  // Untouched.
}

TEST(ReduceInfluences, KeepsLargestFourAndReportsDropped) {
  const Influence in[] = {{3, 0.1f}, {7, 0.3f}, {1, 0.05f}, {2, 0.25f}, {9, 0.2f}, {4, 0.1f}};
  glm::u16vec4 j;
  glm::vec4 w;
  float dropped = -1;
  ASSERT_TRUE(reduceInfluences(in, &j, &w, &dropped).isOk());
  // Kept: 7 (.3), 2 (.25), 9 (.2), then 3 and 4 tie at .1: lower joint (3) wins.
  EXPECT_EQ(j, glm::u16vec4(7, 2, 9, 3));
  EXPECT_NEAR(dropped, 0.15f, 1e-6f);
  EXPECT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-6f);
  EXPECT_NEAR(w.x, 0.3f / 0.85f, 1e-6f);
}

TEST(QuantizeWeights, SumsToOneExactlyAndStaysClose) {
  for (glm::vec4 w : {glm::vec4(1, 0, 0, 0), glm::vec4(0.5f, 0.5f, 0, 0),
                      glm::vec4(1 / 3.0f, 1 / 3.0f, 1 / 3.0f, 0), glm::vec4(0.7f, 0.2f, 0.07f, 0.03f)}) {
    const glm::u16vec4 q = quantizeWeights(w);
    EXPECT_EQ(int(q.x) + q.y + q.z + q.w, 65535);
    const glm::vec4 back = dequantizeWeights(q);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(back[i], w[i], 2.0f / 65535.0f);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(back[i] == 0.0f, w[i] == 0.0f);  // Zeros stay zero.
  }
}

TEST(ReduceInfluences, FewInfluencesAndErrors) {
  const Influence two[] = {{5, 2.0f}, {6, 2.0f}};
  glm::u16vec4 j;
  glm::vec4 w;
  float dropped = -1;
  ASSERT_TRUE(reduceInfluences(two, &j, &w, &dropped).isOk());
  EXPECT_EQ(j, glm::u16vec4(5, 6, 0, 0));
  EXPECT_EQ(w, glm::vec4(0.5f, 0.5f, 0, 0));
  EXPECT_EQ(dropped, 0.0f);
  const Influence zero[] = {{5, 0.0f}};
  EXPECT_EQ(reduceInfluences(zero, &j, &w, nullptr).code(), StatusCode::kInvalidArgument);
  const Influence neg[] = {{5, -1.0f}};
  EXPECT_EQ(reduceInfluences(neg, &j, &w, nullptr).code(), StatusCode::kInvalidArgument);
  const Influence big[] = {{70000, 1.0f}};
  EXPECT_EQ(reduceInfluences(big, &j, &w, nullptr).code(), StatusCode::kOutOfRange);
}

}  // namespace
}  // namespace si
