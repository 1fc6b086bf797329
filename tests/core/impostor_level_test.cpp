// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// si::appendImpostorLevel: every sub-mesh padded to the mesh's levels, one empty level more,
// the mesh still valid; refusals leave the mesh as it was.
#include <gtest/gtest.h>

#include <algorithm>

#include "si/core/default_character.h"
#include "si/core/impostor_level.h"

namespace si {
namespace {

TEST(ImpostorLevel, PadsEverySubMeshThenAddsOneEmptyLevel) {
  Character c;
  ASSERT_TRUE(makeDefaultCharacter({}, &c).isOk());
  SkinnedMesh mesh = c.mesh;
  // One sub-mesh with a shorter chain: padded with its last range.
  mesh.sub_meshes[1].lods.resize(1);
  if (!mesh.sub_meshes[1].lod_error_units.empty()) mesh.sub_meshes[1].lod_error_units.resize(1);
  const size_t levels = mesh.maxLodCount();
  const SkinnedMesh before = mesh;
  ASSERT_TRUE(appendImpostorLevel(&mesh).isOk());
  EXPECT_EQ(mesh.maxLodCount(), levels + 1);
  for (size_t s = 0; s < mesh.sub_meshes.size(); ++s) {
    const SubMesh& sub = mesh.sub_meshes[s];
    ASSERT_EQ(sub.lods.size(), levels + 1) << s;
    EXPECT_EQ(sub.lods.back().index_count, 0u) << s;
    for (size_t l = 0; l < levels; ++l) {
      const IndexRange& was = before.sub_meshes[s].lods[std::min(l, before.sub_meshes[s].lods.size() - 1)];
      EXPECT_EQ(sub.lods[l].first_index, was.first_index) << s << " " << l;
      EXPECT_EQ(sub.lods[l].index_count, was.index_count) << s << " " << l;
    }
    if (!sub.lod_error_units.empty()) {
      EXPECT_EQ(sub.lod_error_units.size(), levels + 1) << s;
    }
  }
  EXPECT_EQ(mesh.triangleCount(0, levels), 0u);
  EXPECT_TRUE(mesh.validate(c.skeleton.jointCount()).isOk());
}

TEST(ImpostorLevel, RefusesWhatItCannotExtend) {
  EXPECT_EQ(appendImpostorLevel(nullptr).code(), StatusCode::kInvalidArgument);
  SkinnedMesh empty;
  EXPECT_EQ(appendImpostorLevel(&empty).code(), StatusCode::kInvalidArgument);
  Character c;
  ASSERT_TRUE(makeDefaultCharacter({}, &c).isOk());
  SkinnedMesh full = c.mesh;
  while (full.maxLodCount() < kMaxImpostorMeshLods)
    full.sub_meshes[0].lods.push_back(full.sub_meshes[0].lods.back());
  full.sub_meshes[0].lod_error_units.clear();
  const size_t levels = full.sub_meshes[0].lods.size();
  EXPECT_EQ(appendImpostorLevel(&full).code(), StatusCode::kLimitExceeded);
  EXPECT_EQ(full.sub_meshes[0].lods.size(), levels);  // Unchanged.
  SkinnedMesh no_lod = c.mesh;
  no_lod.sub_meshes[2].lods.clear();
  EXPECT_EQ(appendImpostorLevel(&no_lod).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(no_lod.sub_meshes[0].lods.size(), c.mesh.sub_meshes[0].lods.size());
}

}  // namespace
}  // namespace si
