// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Generated tangents (si/core/tangents.h) against analytic frames: a plane, its mirror, a
// cylinder's circumference; degenerate mappings, coarse-LOD-only vertices and bad input.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/glm.hpp>

#include "si/core/tangents.h"

namespace si {
namespace {

// Appends a vertex bound rigidly to joint 0.
void addVertex(SkinnedMesh* m, const glm::vec3& p, const glm::vec3& n, const glm::vec2& uv) {
  m->positions.push_back(p);
  m->normals.push_back(n);
  m->texcoords.push_back(uv);
  m->joints.push_back(glm::u16vec4(0));
  m->weights.push_back(glm::vec4(1, 0, 0, 0));
}

// A (cells x cells) grid on z = 0 over [0, 1]^2, normal +z, uv = (su * x, -sv * y): v grows
// down the image as y falls, glTF's convention, so the image's up is +y.
SkinnedMesh grid(int cells, float su, float sv) {
  SkinnedMesh m;
  for (int y = 0; y <= cells; ++y)
    for (int x = 0; x <= cells; ++x) {
      const glm::vec2 p(float(x) / cells, float(y) / cells);
      addVertex(&m, glm::vec3(p, 0.0f), glm::vec3(0, 0, 1), glm::vec2(su * p.x, -sv * p.y));
    }
  const auto at = [&](int x, int y) { return uint32_t(y * (cells + 1) + x); };
  for (int y = 0; y < cells; ++y)
    for (int x = 0; x < cells; ++x)
      m.indices.insert(m.indices.end(), {at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y),
                                         at(x + 1, y + 1), at(x, y + 1)});
  m.sub_meshes.push_back(SubMesh{"grid", {IndexRange{0, uint32_t(m.indices.size())}}, 0, {}});
  return m;
}

double angleDegrees(const glm::vec3& a, const glm::vec3& b) {
  return glm::degrees(std::acos(glm::clamp(double(glm::dot(glm::normalize(a), glm::normalize(b))), -1.0, 1.0)));
}

TEST(Tangents, APlaneMappedAlongItsAxesGetsThoseAxes) {
  SkinnedMesh m = grid(4, 2.0f, 3.0f);  // Unequal scales: the tangent still follows u.
  TangentReport r;
  ASSERT_TRUE(generateTangents(&m, &r).isOk());
  ASSERT_EQ(m.tangents.size(), m.positions.size());
  EXPECT_EQ(r.vertices, m.positions.size());
  EXPECT_EQ(r.degenerate, 0u);
  EXPECT_EQ(r.mirrored, 0u);
  for (const glm::vec4& t : m.tangents) {
    EXPECT_LT(angleDegrees(glm::vec3(t), glm::vec3(1, 0, 0)), 1e-4);
    EXPECT_EQ(t.w, 1.0f);
    EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
  }
  EXPECT_TRUE(m.validate(1).isOk());
}

TEST(Tangents, AMirroredMappingFlipsTheTangentAndItsSign) {
  SkinnedMesh m = grid(3, -1.0f, 1.0f);  // u runs along -x; the image's up still +y.
  TangentReport r;
  ASSERT_TRUE(generateTangents(&m, &r).isOk());
  EXPECT_EQ(r.mirrored, m.positions.size());
  for (const glm::vec4& t : m.tangents) {
    EXPECT_LT(angleDegrees(glm::vec3(t), glm::vec3(-1, 0, 0)), 1e-4);
    EXPECT_EQ(t.w, -1.0f);
    // bitangent = w * cross(N, T) = +y, up in the image (where v falls).
    EXPECT_LT(angleDegrees(t.w * glm::cross(glm::vec3(0, 0, 1), glm::vec3(t)), glm::vec3(0, 1, 0)), 1e-4);
  }
}

TEST(Tangents, ACylinderGetsItsCircumferenceWithinAFractionOfADegree) {
  // 32 segments around z, 4 rings; u = angle / 2pi, v = 1 - z (up the image is up the tube);
  // the seam's vertices duplicated as a glTF file has them.
  const int seg = 32, rings = 4;
  SkinnedMesh m;
  for (int k = 0; k <= rings; ++k)
    for (int i = 0; i <= seg; ++i) {
      const float a = 2.0f * float(M_PI) * float(i) / seg;
      addVertex(&m, glm::vec3(std::cos(a), std::sin(a), float(k) / rings),
                glm::vec3(std::cos(a), std::sin(a), 0.0f),
                glm::vec2(float(i) / seg, 1.0f - float(k) / rings));
    }
  const auto at = [&](int i, int k) { return uint32_t(k * (seg + 1) + i); };
  for (int k = 0; k < rings; ++k)
    for (int i = 0; i < seg; ++i)
      m.indices.insert(m.indices.end(), {at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k),
                                         at(i + 1, k + 1), at(i, k + 1)});
  m.sub_meshes.push_back(SubMesh{"tube", {IndexRange{0, uint32_t(m.indices.size())}}, 0, {}});
  ASSERT_TRUE(generateTangents(&m, nullptr).isOk());
  double worst = 0.0;
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const glm::vec3 around(-m.positions[v].y, m.positions[v].x, 0.0f);  // d(position)/du.
    worst = std::max(worst, angleDegrees(glm::vec3(m.tangents[v]), around));
    EXPECT_EQ(m.tangents[v].w, 1.0f);
    EXPECT_NEAR(glm::dot(glm::vec3(m.tangents[v]), m.normals[v]), 0.0f, 1e-6f);
  }
  // The ends of a row see triangles on one side only: the chord direction, half a segment
  // (5.6 degrees) at most; inner vertices are symmetric.
  EXPECT_LT(worst, 360.0 / seg / 2.0 + 1e-3);
  RecordProperty("worst_angle_degrees", std::to_string(worst));
}

TEST(Tangents, UnusableMappingsAndCoarseOnlyVertices) {
  SkinnedMesh m = grid(2, 1.0f, 1.0f);
  for (glm::vec2& t : m.texcoords) t = glm::vec2(0.5f);  // No gradient anywhere.
  TangentReport r;
  ASSERT_TRUE(generateTangents(&m, &r).isOk());
  EXPECT_EQ(r.degenerate, m.positions.size());
  for (const glm::vec4& t : m.tangents) {
    EXPECT_NEAR(glm::dot(glm::vec3(t), glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
  }
  // A vertex only LOD 1 uses: its frame from LOD 1's triangle.
  m = grid(1, 1.0f, 1.0f);
  const uint32_t extra = uint32_t(m.positions.size());
  addVertex(&m, glm::vec3(2, 0, 0), glm::vec3(0, 0, 1), glm::vec2(0, 2));
  // (0,0) uv (0,0); (1,0) uv (1,0) -> u along +x, and (2,0) uv (0,2): a second triangle.
  m.indices.insert(m.indices.end(), {0, 1, extra});
  m.indices.insert(m.indices.end(), {1, extra, 3});
  m.sub_meshes[0].lods.push_back(IndexRange{6, 6});
  ASSERT_TRUE(generateTangents(&m, &r).isOk());
  EXPECT_EQ(r.degenerate, 0u);
  EXPECT_NEAR(glm::dot(glm::vec3(m.tangents[0]), glm::vec3(1, 0, 0)), 1.0f, 1e-5f);  // LOD 0's.
  EXPECT_NEAR(glm::dot(glm::vec3(m.tangents[extra]), glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
  EXPECT_GT(glm::length(glm::vec3(m.tangents[extra])), 0.99f);
}

TEST(Tangents, BadInputIsRefusedAndLeavesTheMeshAlone) {
  SkinnedMesh m = grid(1, 1.0f, 1.0f);
  EXPECT_EQ(generateTangents(nullptr, nullptr).code(), StatusCode::kInvalidArgument);
  SkinnedMesh no_uv = m;
  no_uv.texcoords.clear();
  const Status s = generateTangents(&no_uv, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("texture coordinates"), std::string::npos) << s.message();
  EXPECT_TRUE(no_uv.tangents.empty());
  SkinnedMesh bad_index = m;
  bad_index.indices[2] = 99;
  EXPECT_EQ(generateTangents(&bad_index, nullptr).code(), StatusCode::kOutOfRange);
  EXPECT_TRUE(bad_index.tangents.empty());
  SkinnedMesh short_normals = m;
  short_normals.normals.pop_back();
  EXPECT_EQ(generateTangents(&short_normals, nullptr).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace si
