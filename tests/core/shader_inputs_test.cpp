// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The vertex stream of the GLSL skinning interface (si/core/shader_inputs.h): the optional words
// (tangent, texture coordinates 1, colour) follow the fixed ones in that order, each only when
// the mesh has it, and hold what the mesh says.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <limits>

#include "core/test_helpers.h"
#include "si/core/default_character.h"
#include "si/core/lod_error.h"
#include "si/core/shader_inputs.h"

namespace si {
namespace {

SkinnedMesh triangle() {
  return test::twoJointTriangle();
}

// A palette that stores both joints of triangle()'s skeleton (all the stream reads of it).
BakedPalette twoJointPalette() {
  BakedPalette p;
  p.palette_joints = {0, 1};
  p.skeleton_to_palette = {0, 1};
  return p;
}

uint32_t wordAt(const VertexStream& s, uint32_t vertex, uint32_t offset) {
  uint32_t w = 0;
  std::memcpy(&w, s.bytes.data() + size_t(vertex) * s.stride_bytes + offset, 4);
  return w;
}

TEST(VertexStream, OptionalWordsFollowTheFixedOnesOnlyWhenTheMeshHasThem) {
  VertexStream plain;
  ASSERT_TRUE(buildVertexStream(triangle(), twoJointPalette(), &plain).isOk());
  EXPECT_EQ(plain.stride_bytes, 32u);
  EXPECT_EQ(plain.tangent_offset, 0u);
  EXPECT_EQ(plain.texcoord1_offset, 0u);
  EXPECT_EQ(plain.color_offset, 0u);

  SkinnedMesh m = triangle();
  m.colors = {{1, 0, 0, 1}, {0, 0.5f, 0, 1}, {0.2f, 0.4f, 0.6f, 0.8f}};
  VertexStream colored;
  ASSERT_TRUE(buildVertexStream(m, twoJointPalette(), &colored).isOk());
  EXPECT_EQ(colored.stride_bytes, 36u);
  EXPECT_EQ(colored.texcoord1_offset, 0u);
  EXPECT_EQ(colored.color_offset, 32u);

  m.texcoords1 = {{0.25f, 0.5f}, {1.5f, -2.0f}, {0.0f, 1.0f}};
  m.tangents.assign(3, glm::vec4(1, 0, 0, -1));
  VertexStream full;
  ASSERT_TRUE(buildVertexStream(m, twoJointPalette(), &full).isOk());
  EXPECT_EQ(full.stride_bytes, 44u);
  EXPECT_EQ(full.tangent_offset, 32u);
  EXPECT_EQ(full.texcoord1_offset, 36u);
  EXPECT_EQ(full.color_offset, 40u);
  for (uint32_t v = 0; v < 3; ++v) {
    SCOPED_TRACE(v);
    EXPECT_EQ(wordAt(full, v, full.tangent_offset), packTangent10(m.tangents[v]));
    const uint32_t uv = wordAt(full, v, full.texcoord1_offset);
    EXPECT_EQ(halfToFloat(uint16_t(uv & 0xFFFF)), m.texcoords1[v].x);
    EXPECT_EQ(halfToFloat(uint16_t(uv >> 16)), m.texcoords1[v].y);
    const uint32_t rgba = wordAt(full, v, full.color_offset);
    EXPECT_EQ(rgba, packColor8(m.colors[v]));
    for (int c = 0; c < 4; ++c)  // 8 bits a channel: within half a step.
      EXPECT_NEAR(float((rgba >> (8 * c)) & 0xFF) / 255.0f, m.colors[v][c], 0.5001f / 255.0f) << c;
    // The fixed words do not move.
    EXPECT_EQ(wordAt(full, v, VertexStream::kNormalOffset),
              wordAt(plain, v, VertexStream::kNormalOffset));
  }
  EXPECT_EQ(packColor8(glm::vec4(1.0f, 0.0f, 0.5f, 2.0f)), 0xFF8000FFu) << "R low; clamped";
}

TEST(VertexStream, TheMeshRefusesColoursOutsideTheUnitRangeAndMismatchedCounts) {
  SkinnedMesh m = triangle();
  m.colors = {{1, 0, 0, 1}, {0, 1.5f, 0, 1}, {0, 0, 1, 1}};
  VertexStream s;
  EXPECT_EQ(buildVertexStream(m, twoJointPalette(), &s).code(), StatusCode::kOutOfRange);
  m.colors[1].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(m.validate(2).code(), StatusCode::kNotFinite);
  m.colors[1].y = -0.01f;
  EXPECT_EQ(m.validate(2).code(), StatusCode::kOutOfRange);
  m.colors.pop_back();
  EXPECT_EQ(m.validate(2).code(), StatusCode::kCountMismatch);
  m = triangle();
  m.texcoords1 = {{0, 0}, {0, 0}};
  EXPECT_EQ(m.validate(2).code(), StatusCode::kCountMismatch);
  m.texcoords1.push_back({std::numeric_limits<float>::infinity(), 0});
  EXPECT_EQ(m.validate(2).code(), StatusCode::kNotFinite);
  EXPECT_EQ(s.stride_bytes, 0u) << "a refused stream is left untouched";
}

// Each LOD level's morph cut is the share of its error (levels past the mesh's take its
// coarsest); unmeasured levels cut nothing; a share outside [0, 1] is refused by name.
TEST(MorphLodCuts, EachLevelCutsItsShareOfItsError) {
  Character c;
  ASSERT_TRUE(makeDefaultCharacter({}, &c).isOk());
  std::vector<float> levels;
  ASSERT_TRUE(lodErrorsByLevel(c.mesh, &levels).isOk());
  ASSERT_GE(levels.size(), 2u);
  ASSERT_GT(levels.back(), 0.0f);
  std::array<float, kMorphLodCuts> cuts{};
  ASSERT_TRUE(morphLodCuts(c.mesh, 0.5f, &cuts).isOk());
  for (size_t k = 0; k < cuts.size(); ++k)
    EXPECT_FLOAT_EQ(cuts[k], 0.5f * levels[std::min(k, levels.size() - 1)]) << "level " << k;
  EXPECT_EQ(cuts[0], 0.0f);  // LOD 0 keeps every target.
  for (float bad : {-0.1f, 1.5f, std::numeric_limits<float>::quiet_NaN()}) {
    const std::array<float, kMorphLodCuts> before = cuts;
    const Status s = morphLodCuts(c.mesh, bad, &cuts);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(s.message().find("share"), std::string::npos) << s.toString();
    EXPECT_EQ(cuts, before) << "nothing written";
  }
  EXPECT_EQ(morphLodCuts(c.mesh, 0.5f, nullptr).code(), StatusCode::kInvalidArgument);
  for (SubMesh& m : c.mesh.sub_meshes) m.lod_error_units.clear();
  ASSERT_TRUE(morphLodCuts(c.mesh, 0.5f, &cuts).isOk());
  for (float cut : cuts) EXPECT_EQ(cut, 0.0f);
}

}  // namespace
}  // namespace si
