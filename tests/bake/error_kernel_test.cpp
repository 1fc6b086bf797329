// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The measurement's inner loops against the plain computations they replace.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>

#include "bake/error_kernel.h"
#include "si/core/baked_palette.h"
#include "si/core/reference_evaluator.h"

namespace si::detail {
namespace {

TEST(ErrorKernel, LargestKIsTheKthLargestOfTheStream) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (uint64_t k : {1u, 3u, 100u, 999u}) {
    std::vector<float> all;
    LargestK largest(k);
    for (int i = 0; i < 5000; ++i) {
      // Rising, falling and repeated values: the threshold moves both ways through the stream.
      const float e = i % 7 == 0 ? 0.5f : u(rng) * float(1 + (i / 1000) % 3);
      all.push_back(e);
      largest.add(e);
    }
    std::nth_element(all.begin(), all.begin() + std::ptrdiff_t(k - 1), all.end(), std::greater<float>());
    EXPECT_EQ(largest.kth(), all[k - 1]) << "k=" << k;
  }
  // After a trim, a value between the kept ones still enters: {10, 9, 8} kept, then 9.5.
  LargestK three(3);
  for (float e : {10.0f, 9.0f, 8.0f, 1.0f, 1.0f, 1.0f, 9.5f}) three.add(e);
  EXPECT_EQ(three.kth(), 9.0f);
  LargestK few(10);
  few.add(2.0f);
  few.add(1.0f);
  EXPECT_EQ(few.kth(), 1.0f);  // Fewer than k: the smallest.
}

// Random influences (tiny and zero weights, a weight quantized away), random matrices: each
// vertex's error is the distance between emulateSkinning() and skinVertices().
TEST(ErrorKernel, GroupsGiveEachVertexsShaderMinusReferenceDistance) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const size_t nj = 6, nv = 300;
  SkinnedMesh mesh;
  for (size_t v = 0; v < nv; ++v) {
    mesh.positions.push_back({u(rng), u(rng), u(rng)});
    mesh.normals.push_back({0, 1, 0});
    mesh.joints.push_back(glm::u16vec4(v % nj, (v + 1) % nj, (v + 3) % nj, (v + 4) % nj));
    glm::vec4 w = v % 5 == 0 ? glm::vec4(1, 0, 0, 0)
                  : v % 5 == 1 ? glm::vec4(0.5f, 0.5f, 0, 0)
                               : glm::vec4(0.6f, 0.3f, 0.1f - 1e-6f, 1e-6f);
    mesh.weights.push_back(w);
  }
  SkinnedMesh gpu = mesh;
  for (glm::vec4& w : gpu.weights) w = dequantizeWeights(quantizeWeights(w));
  std::vector<glm::dmat4> reference(nj);
  std::vector<glm::mat4> emulated(nj);
  for (size_t j = 0; j < nj; ++j) {
    glm::dmat4 m(1.0);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r) m[c][r] += 0.3 * u(rng);
    reference[j] = m;
    emulated[j] = glm::mat4(m);
    emulated[j][3][0] += 1e-4f * float(j);  // The shader's own error, per joint.
  }
  std::vector<uint32_t> vertices;
  for (uint32_t v = 0; v < nv; v += 2) vertices.push_back(v);
  const InfluenceGroups groups(mesh, gpu, vertices);
  ASSERT_EQ(groups.size(), vertices.size());
  EXPECT_LT(groups.groupCount(), vertices.size());  // Equal influences share a group.
  std::vector<float> errors;
  groups.errors(emulated, reference, &errors);
  std::vector<glm::vec3> shader(nv);
  std::vector<glm::dvec3> exact(nv);
  ASSERT_TRUE(emulateSkinning(gpu, emulated, shader, {}).isOk());
  ASSERT_TRUE(skinVertices(mesh, reference, exact, {}, {}).isOk());
  std::vector<glm::vec3> positions;
  groups.positions(emulated, &positions);
  for (size_t s = 0; s < groups.size(); ++s) {
    const uint32_t v = groups.vertex(s);
    const double expected = glm::length(glm::dvec3(shader[v]) - exact[v]);
    EXPECT_NEAR(errors[s], expected, 1e-6 + 1e-3 * expected) << "vertex " << v;
    EXPECT_NEAR(glm::length(positions[s] - shader[v]), 0.0f, 1e-5f) << "vertex " << v;
  }
}

}  // namespace
}  // namespace si::detail
