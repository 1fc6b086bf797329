// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// LOD chains on the embedded character: deep enough for a character a few pixels tall, errors
// that grow along the chain and are never below the measured surface distance; validity.
#include <gtest/gtest.h>

#include "core/test_helpers.h"
#include "si/bake/lod_chain.h"
#include "si/core/default_character.h"
#include "si/core/lod_error.h"

namespace si {
namespace {

TEST(LodChain, ReachesAFewDozenTrianglesWithHonestErrors) {
  Character c = test::embeddedCharacter();
  LodChainReport report;
  ASSERT_TRUE(buildLodChain(&c.mesh, {}, &report).isOk());
  ASSERT_TRUE(c.validate().isOk());
  const SubMesh& body = c.mesh.sub_meshes[0];
  ASSERT_GE(body.lods.size(), 5u);                      // 3 kept + generated.
  EXPECT_LE(body.lods.back().index_count / 3, 60u);     // A few dozen triangles at most.
  for (const SubMesh& sm : c.mesh.sub_meshes) {
    ASSERT_EQ(sm.lod_error_units.size(), sm.lods.size());
    for (size_t l = 1; l < sm.lods.size(); ++l) {
      EXPECT_LT(sm.lods[l].index_count, sm.lods[l - 1].index_count) << sm.name << " " << l;
      EXPECT_GE(sm.lod_error_units[l], sm.lod_error_units[l - 1]) << sm.name << " " << l;
      // Never below the measured distance from LOD 0.
      const auto span = [&](size_t k) {
        return Span<const uint32_t>(c.mesh.indices.data() + sm.lods[k].first_index,
                                    sm.lods[k].index_count);
      };
      float measured = 0.0f;
      ASSERT_TRUE(surfaceDistance(c.mesh.positions, span(0), span(l), &measured).isOk());
      EXPECT_GE(sm.lod_error_units[l], measured * 0.999f) << sm.name << " " << l;
    }
  }
  // The report lists every level, kept and generated.
  size_t generated = 0;
  for (const LodLevelReport& l : report.levels) generated += l.generated;
  EXPECT_GE(generated, 2u);
  size_t total = 0;
  for (const SubMesh& sm : c.mesh.sub_meshes) total += sm.lods.size();
  EXPECT_EQ(report.levels.size(), total);
}

TEST(LodChain, RebuildingReplacesEveryLevelButTheFirst) {
  Character c = test::embeddedCharacter();
  LodChainDesc d;
  d.keep_existing = false;
  d.level_count = 4;
  d.triangle_ratio = 0.5f;
  ASSERT_TRUE(buildLodChain(&c.mesh, d, nullptr).isOk());
  ASSERT_TRUE(c.validate().isOk());
  const SubMesh& body = c.mesh.sub_meshes[0];
  ASSERT_EQ(body.lods.size(), 4u);
  EXPECT_EQ(body.lods[0].index_count, 4104u * 3);
  EXPECT_LE(body.lods[1].index_count / 3, 2052u);
  // Only the levels in use are in the index buffer.
  size_t used = 0;
  for (const SubMesh& sm : c.mesh.sub_meshes)
    for (const IndexRange& r : sm.lods) used += r.index_count;
  EXPECT_EQ(used, c.mesh.indices.size());
}

TEST(LodChain, ValidityMatrix) {
  Character c = test::embeddedCharacter();
  const SkinnedMesh before = c.mesh;
  EXPECT_EQ(buildLodChain(nullptr, {}, nullptr).code(), StatusCode::kInvalidArgument);
  LodChainDesc d;
  d.level_count = 9;
  EXPECT_EQ(buildLodChain(&c.mesh, d, nullptr).code(), StatusCode::kInvalidArgument);
  d = LodChainDesc();
  d.triangle_ratio = 1.5f;
  EXPECT_EQ(buildLodChain(&c.mesh, d, nullptr).code(), StatusCode::kInvalidArgument);
  SkinnedMesh broken = c.mesh;
  broken.sub_meshes[0].lods[0].index_count = 1;
  EXPECT_FALSE(buildLodChain(&broken, {}, nullptr).isOk());
  EXPECT_EQ(c.mesh.indices, before.indices);  // Untouched by every failure.
  EXPECT_EQ(c.mesh.sub_meshes.size(), before.sub_meshes.size());
  EXPECT_EQ(c.mesh.sub_meshes[0].lods.size(), before.sub_meshes[0].lods.size());
}

}  // namespace
}  // namespace si
