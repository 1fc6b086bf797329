// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A mesh with a second set of influences (SkinnedMesh::joints1/weights1): validated and
// normalized over both sets, skinned by the reference with all 8, quantized so the 8 stored
// weights sum to exactly 65535, and written into the vertex stream after the optional words.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "core/test_helpers.h"
#include "si/core/reference_evaluator.h"
#include "si/core/shader_inputs.h"

namespace si {
namespace {

// 8 joints; vertex v weighted to all of them, its largest weight on joint v.
SkinnedMesh eightInfluenceTriangle() {
  SkinnedMesh m = test::twoJointTriangle();
  m.joints1.resize(3);
  m.weights1.resize(3);
  const float w[8] = {0.3f, 0.2f, 0.15f, 0.11f, 0.09f, 0.07f, 0.05f, 0.03f};
  for (size_t v = 0; v < 3; ++v)
    for (int k = 0; k < 8; ++k) {
      const uint16_t j = uint16_t((k + v) % 8);
      if (k < 4) {
        m.joints[v][k] = j;
        m.weights[v][k] = w[k];
      } else {
        m.joints1[v][k - 4] = j;
        m.weights1[v][k - 4] = w[k];
      }
    }
  return m;
}

TEST(EightInfluences, ValidateAndNormalizeReadBothSets) {
  SkinnedMesh m = eightInfluenceTriangle();
  EXPECT_EQ(m.influenceCount(), 8u);
  EXPECT_TRUE(m.validate(8).isOk()) << m.validate(8).toString();
  EXPECT_EQ(m.validate(7).code(), StatusCode::kOutOfRange);  // A joint of the second set.
  SkinnedMesh half = m;
  half.weights1.pop_back();
  EXPECT_EQ(half.validate(8).code(), StatusCode::kCountMismatch);
  SkinnedMesh one_set = m;
  one_set.weights1.clear();
  EXPECT_EQ(one_set.validate(8).code(), StatusCode::kCountMismatch);
  SkinnedMesh first_only = m;  // Only the first set's weights: they sum to 0.76.
  first_only.weights1.assign(3, glm::vec4(0.0f));
  EXPECT_EQ(first_only.validate(8).code(), StatusCode::kInvalidArgument);
  SkinnedMesh doubled = m;
  for (glm::vec4& w : doubled.weights) w *= 2.0f;
  for (glm::vec4& w : doubled.weights1) w *= 2.0f;
  EXPECT_FALSE(doubled.validate(8).isOk());
  WeightNormalizationReport r;
  ASSERT_TRUE(normalizeWeights(doubled, &r).isOk());
  EXPECT_EQ(r.vertices_changed, 3u);
  EXPECT_NEAR(r.max_correction, 1.0f, 1e-6f);
  for (size_t v = 0; v < 3; ++v) {
    EXPECT_NEAR(doubled.weights[v].x, m.weights[v].x, 1e-7f);
    EXPECT_NEAR(doubled.weights1[v].w, m.weights1[v].w, 1e-7f);
  }
  EXPECT_TRUE(doubled.validate(8).isOk());
}

TEST(EightInfluences, TheReferenceSkinsWithAllEight) {
  const SkinnedMesh m = eightInfluenceTriangle();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<glm::dmat4> skinning(8);
  for (glm::dmat4& s : skinning)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r) s[c][r] = u(rng);
  std::vector<glm::dvec3> positions(3);
  ASSERT_TRUE(skinVertices(m, skinning, positions, {}, {}).isOk());
  for (size_t v = 0; v < 3; ++v) {
    glm::dvec3 expected(0.0);
    const glm::dvec4 p(glm::dvec3(m.positions[v]), 1.0);
    for (int k = 0; k < 4; ++k) {
      expected += double(m.weights[v][k]) * glm::dvec3(skinning[m.joints[v][k]] * p);
      expected += double(m.weights1[v][k]) * glm::dvec3(skinning[m.joints1[v][k]] * p);
    }
    EXPECT_LT(glm::length(positions[v] - expected), 1e-12) << v;
  }
  // And what the GPU does with the same matrices in float.
  std::vector<glm::mat4> f(skinning.begin(), skinning.end());
  std::vector<glm::vec3> emulated(3);
  ASSERT_TRUE(emulateSkinning(m, f, emulated, {}).isOk());
  for (size_t v = 0; v < 3; ++v)
    EXPECT_LT(glm::length(glm::dvec3(emulated[v]) - positions[v]), 1e-5) << v;
}

TEST(EightInfluences, QuantizedTogetherTheyMakeExactlyOne) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int trial = 0; trial < 1000; ++trial) {
    float w[8], sum = 0.0f;
    for (float& x : w) sum += (x = u(rng) * u(rng));
    for (float& x : w) x /= sum;
    glm::u16vec4 q, q1;
    quantizeWeights(glm::vec4(w[0], w[1], w[2], w[3]), glm::vec4(w[4], w[5], w[6], w[7]), &q, &q1);
    int total = 0;
    for (int k = 0; k < 4; ++k) total += q[k] + q1[k];
    ASSERT_EQ(total, 65535) << trial;
    for (int k = 0; k < 4; ++k) {
      EXPECT_NEAR(q[k] / 65535.0f, w[k], 8.0f / 65535.0f) << trial;
      EXPECT_NEAR(q1[k] / 65535.0f, w[k + 4], 8.0f / 65535.0f) << trial;
    }
  }
}

TEST(EightInfluences, TheStreamCarriesTheSecondSetLast) {
  const SkinnedMesh m = eightInfluenceTriangle();
  BakedPalette p;
  p.palette_joints = {0, 1, 2, 3, 4, 5, 6, 7};
  p.skeleton_to_palette = {7, 6, 5, 4, 3, 2, 1, 0};  // Slots differ from joints.
  VertexStream s;
  ASSERT_TRUE(buildVertexStream(m, p, &s).isOk());
  EXPECT_EQ(s.joints1_offset, 32u);
  EXPECT_EQ(s.weights1_offset, 36u);
  EXPECT_EQ(s.stride_bytes, 44u);
  for (uint32_t v = 0; v < 3; ++v) {
    const uint8_t* vertex = s.bytes.data() + size_t(v) * s.stride_bytes;
    glm::u16vec4 q, q1;
    quantizeWeights(m.weights[v], m.weights1[v], &q, &q1);
    glm::u16vec4 stored, stored1;
    std::memcpy(&stored, vertex + s.weights_offset, 8);
    std::memcpy(&stored1, vertex + s.weights1_offset, 8);
    EXPECT_EQ(stored, q) << v;
    EXPECT_EQ(stored1, q1) << v;
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(vertex[VertexStream::kJointsOffset + k], 7 - m.joints[v][k]) << v;
      EXPECT_EQ(vertex[s.joints1_offset + k], 7 - m.joints1[v][k]) << v;
    }
  }
  // Past 256 stored joints both sets are wide (4 x uint16), the second right after the fixed
  // 36 bytes, where the pre-skinning source reads it (9 words in).
  BakedPalette wide;
  for (uint16_t j = 0; j < 300; ++j) {
    wide.palette_joints.push_back(j);
    wide.skeleton_to_palette.push_back(int32_t(299 - j));
  }
  VertexStream w;
  ASSERT_TRUE(buildVertexStream(m, wide, &w).isOk());
  EXPECT_TRUE(w.wide_joints);
  EXPECT_EQ(w.joints1_offset, 36u);
  EXPECT_EQ(w.weights1_offset, 44u);
  EXPECT_EQ(w.stride_bytes, 52u);
  for (uint32_t v = 0; v < 3; ++v) {
    glm::u16vec4 joints1;
    std::memcpy(&joints1, w.bytes.data() + size_t(v) * w.stride_bytes + w.joints1_offset, 8);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(joints1[k], 299 - m.joints1[v][k]) << v;
  }
  // A palette that leaves out a joint of the second set refuses the mesh by the joint.
  p.skeleton_to_palette[m.joints1[0][3]] = -1;
  const Status refused = buildVertexStream(m, p, &s);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.message().find("which the palette does not store"), std::string::npos);
}

}  // namespace
}  // namespace si
