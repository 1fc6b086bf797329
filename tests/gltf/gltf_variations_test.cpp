// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Parts and variation groups: any number of primitives and materials imports; always-worn
// parts merge into one sub-mesh with per-vertex materials; variation groups come from the
// "VAR_" convention, from explicit groups or one per mesh; LOD levels merge per group.
#include <gtest/gtest.h>

#include "gltf/parts_asset.h"
#include "si/bake/animation_baker.h"
#include "si/gltf/gltf_import.h"

namespace si {
namespace {

using test::PartsMesh;

Status importJson(const std::string& json, const GltfImportDesc& d, Character* c,
                  GltfImportReport* r) {
  return importGltfMemory(
      Span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()), "", d, c, r);
}

TEST(GltfVariations, TwoHundredPrimitivesAndAHundredMaterialsImportAsOnePart) {
  Character c;
  GltfImportReport r;
  ASSERT_TRUE(importJson(test::partsAsset({{"Body", 200}}, 100), {}, &c, &r).isOk());
  EXPECT_EQ(r.skinned_primitives, 200u);
  EXPECT_EQ(r.parts, 200u);
  ASSERT_EQ(c.mesh.sub_meshes.size(), 1u);
  EXPECT_EQ(c.mesh.sub_meshes[0].name, "base");
  ASSERT_EQ(c.mesh.sub_meshes[0].lods.size(), 1u);
  EXPECT_EQ(c.mesh.sub_meshes[0].lods[0].index_count, 200u * 6);
  ASSERT_EQ(r.groups.size(), 1u);
  EXPECT_EQ(r.groups[0].parts, 200u);
  EXPECT_EQ(r.groups[0].materials, 100u);
  EXPECT_EQ(r.groups[0].source, "always worn");
  ASSERT_EQ(c.materials.size(), 101u);  // The default white, then the file's.
  EXPECT_EQ(r.materials, 101u);
  ASSERT_EQ(c.mesh.vertex_materials.size(), c.mesh.vertexCount());
  ASSERT_EQ(c.mesh.vertexCount(), 800u);
  for (uint32_t k = 0; k < 200; ++k)
    for (uint32_t v = 0; v < 4; ++v)
      ASSERT_EQ(c.mesh.vertex_materials[k * 4 + v], k % 100 + 1) << "primitive " << k;
  // Material 37 of the file is the 38th: its factor as written.
  EXPECT_NEAR(c.materials[38].base_color_factor.r, float(37 % 5) / 4.0f, 1e-6f);
  EXPECT_NEAR(c.materials[38].base_color_factor.g, float((37 / 5) % 5) / 4.0f, 1e-6f);
  // It bakes.
  BakedPalette p;
  ASSERT_TRUE(bakePalette(c, BakeDesc{}, &p, nullptr).isOk());
}

TEST(GltfVariations, GroupsByConventionMergeTheirPartsAndLevels) {
  Character c;
  GltfImportReport r;
  const std::string json = test::partsAsset(
      {{"Body", 190}, {"VAR_Helmet", 5, true}, {"Cloak", 3}, {"var_Sword", 2}}, 7);
  ASSERT_TRUE(importJson(json, {}, &c, &r).isOk());
  ASSERT_EQ(c.mesh.sub_meshes.size(), 3u);
  EXPECT_EQ(c.mesh.sub_meshes[0].name, "base");  // Body and Cloak, always worn, first.
  EXPECT_EQ(c.mesh.sub_meshes[1].name, "Helmet");
  EXPECT_EQ(c.mesh.sub_meshes[2].name, "Sword");
  EXPECT_EQ(r.parts, 200u);
  ASSERT_EQ(r.groups.size(), 3u);
  EXPECT_EQ(r.groups[0].parts, 193u);
  EXPECT_EQ(r.groups[1].parts, 5u);
  EXPECT_EQ(r.groups[1].source, "convention");
  // The helmet's two levels: five quads, then five triangles.
  const SubMesh& helmet = c.mesh.sub_meshes[1];
  ASSERT_EQ(helmet.lods.size(), 2u);
  EXPECT_EQ(helmet.lods[0].index_count, 30u);
  EXPECT_EQ(helmet.lods[1].index_count, 15u);
  EXPECT_EQ(c.mesh.sub_meshes[0].lods.size(), 1u);
  EXPECT_EQ(c.mesh.sub_meshes[0].lods[0].index_count, 193u * 6);
  // Every primitive is drawn: the LOD 0 ranges cover each quad's two triangles once.
  size_t drawn = 0;
  for (const SubMesh& sm : c.mesh.sub_meshes) drawn += sm.lods[0].index_count;
  EXPECT_EQ(drawn, 200u * 6);
}

TEST(GltfVariations, ExplicitGroupsWinAndBadOnesAreRefused) {
  const std::string json =
      test::partsAsset({{"Body", 100}, {"Hat", 50}, {"Cape", 40}, {"VAR_Bag", 10}}, 10);
  GltfImportDesc d;
  d.variation_groups = {{"Headwear", {"Hat"}}, {"Back", {"Cape_node", "VAR_Bag"}}};
  Character c;
  GltfImportReport r;
  ASSERT_TRUE(importJson(json, d, &c, &r).isOk());
  ASSERT_EQ(c.mesh.sub_meshes.size(), 3u);
  EXPECT_EQ(c.mesh.sub_meshes[0].name, "base");
  EXPECT_EQ(c.mesh.sub_meshes[1].name, "Headwear");
  EXPECT_EQ(c.mesh.sub_meshes[2].name, "Back");  // The node name and the VAR_ mesh, by option.
  EXPECT_EQ(r.groups[2].parts, 50u);
  EXPECT_EQ(r.groups[2].source, "option");
  EXPECT_EQ(c.mesh.sub_meshes[2].lods[0].index_count, 50u * 6);

  const Character before = c;
  d.variation_groups = {{"Headwear", {"Hat", "Scarf"}}};
  Status s = importJson(json, d, &c, &r);
  EXPECT_EQ(s.code(), StatusCode::kNotFound);
  EXPECT_NE(s.message().find("Scarf"), std::string::npos) << s.message();
  EXPECT_EQ(c.mesh.sub_meshes.size(), before.mesh.sub_meshes.size());  // Untouched.
  d.variation_groups = {{"", {"Hat"}}};
  EXPECT_EQ(importJson(json, d, &c, &r).code(), StatusCode::kInvalidArgument);
  d.variation_groups = {{"A", {"Hat"}}, {"A", {"Cape"}}};
  EXPECT_EQ(importJson(json, d, &c, &r).code(), StatusCode::kInvalidArgument);
}

TEST(GltfVariations, EachMeshAGroupUpToThirtyTwo) {
  std::vector<PartsMesh> meshes;
  for (int i = 0; i < 40; ++i) meshes.push_back({"Piece" + std::to_string(i), 2});
  const std::string json = test::partsAsset(meshes, 3);
  GltfImportDesc d;
  d.variations = VariationSource::kEachMesh;
  Character c;
  GltfImportReport r;
  const Status s = importJson(json, d, &c, &r);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("40 variation groups"), std::string::npos) << s.message();
  // The default (convention) imports the same file as one always-worn group.
  ASSERT_TRUE(importJson(json, {}, &c, &r).isOk());
  EXPECT_EQ(c.mesh.sub_meshes.size(), 1u);
  // Thirty-two meshes, one group each, named after them.
  meshes.resize(32);
  ASSERT_TRUE(importJson(test::partsAsset(meshes, 3), d, &c, &r).isOk());
  ASSERT_EQ(c.mesh.sub_meshes.size(), 32u);
  EXPECT_EQ(c.mesh.sub_meshes[5].name, "Piece5");
  EXPECT_EQ(r.groups[5].source, "each mesh");
}

}  // namespace
}  // namespace si
