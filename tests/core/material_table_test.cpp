// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Per-vertex materials and the material table: validation, resolution from sub-meshes, the
// texture array's layers and the documented resize filter.
#include <gtest/gtest.h>

#include <cmath>

#include "core/test_helpers.h"
#include "si/core/default_character.h"
#include "si/core/material_table.h"

namespace si {
namespace {

Image solid(uint32_t w, uint32_t h, glm::u8vec4 c) {
  Image img;
  img.width = w;
  img.height = h;
  for (uint32_t i = 0; i < w * h; ++i) img.rgba8.insert(img.rgba8.end(), {c.r, c.g, c.b, c.a});
  return img;
}

TEST(MaterialTable, VertexMaterialsAreValidated) {
  Character c = test::embeddedCharacter();
  c.materials.resize(3);
  c.mesh.vertex_materials.assign(c.mesh.vertexCount() - 1, 0);
  EXPECT_EQ(c.validate().code(), StatusCode::kCountMismatch);
  c.mesh.vertex_materials.assign(c.mesh.vertexCount(), 2);
  EXPECT_TRUE(c.validate().isOk());
  c.mesh.vertex_materials[7] = 3;
  const Status s = c.validate();
  EXPECT_EQ(s.code(), StatusCode::kOutOfRange);
  EXPECT_NE(s.message().find("vertex 7"), std::string::npos) << s.message();
}

TEST(MaterialTable, MetallicRoughnessMaterialsAreValidated) {
  Character c = test::embeddedCharacter();
  c.images = {solid(2, 2, {128, 128, 255, 255})};
  c.materials.assign(1, Material{});
  EXPECT_TRUE(c.validate().isOk());
  const auto broken = [&](auto edit, StatusCode code, const char* words) {
    Character d = c;
    edit(d.materials[0]);
    const Status s = d.validate();
    EXPECT_EQ(s.code(), code) << s.message();
    EXPECT_NE(s.message().find(words), std::string::npos) << s.message();
  };
  broken([](Material& m) { m.metallic_factor = 1.5f; }, StatusCode::kOutOfRange, "[0, 1]");
  broken([](Material& m) { m.roughness_factor = -0.1f; }, StatusCode::kOutOfRange, "[0, 1]");
  broken([](Material& m) { m.occlusion_strength = 2.0f; }, StatusCode::kOutOfRange, "[0, 1]");
  broken([](Material& m) { m.emissive_factor.y = -1.0f; }, StatusCode::kOutOfRange, "emissive");
  broken([](Material& m) { m.alpha_cutoff = -0.5f; }, StatusCode::kOutOfRange, "cutoff");
  broken([](Material& m) { m.normal_scale = NAN; }, StatusCode::kNotFinite, "not finite");
  broken([](Material& m) { m.emissive_image = 1; }, StatusCode::kOutOfRange, "image 1 of 1");
  broken([](Material& m) { m.occlusion_image = -2; }, StatusCode::kOutOfRange, "image -2");
  broken([](Material& m) { m.alpha_mode = AlphaMode(7); }, StatusCode::kOutOfRange, "alpha mode");
  // A normal map needs the mesh's tangents.
  c.mesh.tangents.clear();
  broken([](Material& m) { m.normal_image = 0; }, StatusCode::kInvalidArgument, "tangents");
  c.mesh.tangents.assign(c.mesh.vertexCount(), glm::vec4(1, 0, 0, 1));
  c.materials[0].normal_image = 0;
  EXPECT_TRUE(c.validate().isOk());
}

TEST(MaterialTable, VerticesTakeTheirSubMeshMaterialUnlessSet) {
  Character c = test::embeddedCharacter();
  ASSERT_GE(c.mesh.sub_meshes.size(), 2u);
  c.materials.resize(c.mesh.sub_meshes.size());
  for (size_t s = 0; s < c.mesh.sub_meshes.size(); ++s) c.mesh.sub_meshes[s].material = uint32_t(s);
  const std::vector<uint16_t> resolved = resolvedVertexMaterials(c.mesh);
  ASSERT_EQ(resolved.size(), c.mesh.vertexCount());
  for (size_t s = 0; s < c.mesh.sub_meshes.size(); ++s) {
    const IndexRange r = c.mesh.sub_meshes[s].lods[0];
    for (uint32_t i = r.first_index; i < r.first_index + r.index_count; ++i)
      EXPECT_EQ(resolved[c.mesh.indices[i]], s);
  }
  c.mesh.vertex_materials.assign(c.mesh.vertexCount(), 1);
  EXPECT_EQ(resolvedVertexMaterials(c.mesh), c.mesh.vertex_materials);
}

TEST(MaterialTable, ImagesBecomeLayersOfOneSize) {
  Character c = test::embeddedCharacter();
  c.images = {solid(4, 2, {10, 20, 30, 40}), solid(8, 8, {200, 100, 50, 255}),
              solid(2, 2, {1, 2, 3, 4})};  // The third is used by no material.
  c.materials.assign(4, Material{});
  c.materials[0].base_color_image = 1;
  c.materials[1].base_color_image = 0;
  c.materials[2].base_color_image = 1;  // Shares the layer of material 0.
  c.materials[3].base_color_factor = glm::vec4(0.5f);  // No image: the white layer.
  c.mesh.vertex_materials.assign(c.mesh.vertexCount(), 3);
  MaterialTable t;
  ASSERT_TRUE(buildMaterialTable(c, 0, &t).isOk());
  EXPECT_EQ(t.width, 8u);
  EXPECT_EQ(t.height, 8u);
  ASSERT_EQ(t.layers.size(), 3u);  // White, image 1, image 0.
  EXPECT_EQ(t.resized_images, 1u);
  ASSERT_EQ(t.materials.size(), 4u);
  EXPECT_EQ(t.materials[0].layer, t.materials[2].layer);
  EXPECT_NE(t.materials[0].layer, t.materials[1].layer);
  EXPECT_EQ(t.materials[3].layer, 0u);
  EXPECT_EQ(t.materials[3].base_color_factor, glm::vec4(0.5f));
  for (const Image& l : t.layers) {
    EXPECT_EQ(l.width, 8u);
    EXPECT_EQ(l.height, 8u);
    EXPECT_TRUE(l.validate().isOk());
  }
  EXPECT_EQ(t.layers[0].rgba8[5], 255);
  EXPECT_EQ(t.layers[t.materials[1].layer].rgba8[0], 10);  // A solid image stays solid.
  EXPECT_EQ(t.layers[t.materials[1].layer].rgba8[3], 40);
  EXPECT_EQ(t.vertex_materials, c.mesh.vertex_materials);
  // The cap.
  ASSERT_TRUE(buildMaterialTable(c, 4, &t).isOk());
  EXPECT_EQ(t.width, 4u);
  EXPECT_EQ(t.height, 4u);
  EXPECT_EQ(t.resized_images, 2u);
  // No materials: one white entry, one white layer.
  c.materials.clear();
  c.mesh.vertex_materials.clear();
  ASSERT_TRUE(buildMaterialTable(c, 0, &t).isOk());
  ASSERT_EQ(t.materials.size(), 1u);
  ASSERT_EQ(t.layers.size(), 1u);
  EXPECT_EQ(t.layers[0].width, 1u);
  EXPECT_EQ(buildMaterialTable(c, 0, nullptr).code(), StatusCode::kInvalidArgument);
  c.mesh.vertex_materials.assign(c.mesh.vertexCount(), 5);
  EXPECT_EQ(buildMaterialTable(c, 0, &t).code(), StatusCode::kOutOfRange);
}

TEST(MaterialTable, ColourAndDataImagesGoToTheirOwnArrays) {
  Character c = test::embeddedCharacter();
  c.images = {solid(4, 4, {200, 100, 50, 255}), solid(2, 2, {128, 128, 255, 255}),
              solid(8, 2, {0, 200, 100, 255}), solid(2, 2, {90, 0, 0, 255})};
  c.mesh.tangents.assign(c.mesh.vertexCount(), glm::vec4(1, 0, 0, 1));
  c.materials.assign(2, Material{});
  Material& m = c.materials[0];
  m.base_color_image = 0;
  m.emissive_image = 0;  // The same image as colour twice: one layer.
  m.normal_image = 1;
  m.metallic_roughness_image = 2;
  m.occlusion_image = 3;
  m.metallic_factor = 0.3f;
  m.roughness_factor = 0.7f;
  m.normal_scale = 0.5f;
  m.occlusion_strength = 0.25f;
  m.emissive_factor = glm::vec3(1.0f, 0.5f, 0.0f);
  m.alpha_mode = AlphaMode::kMask;
  m.alpha_cutoff = 0.4f;
  m.double_sided = true;
  c.materials[1].alpha_mode = AlphaMode::kBlend;  // Drawn opaque.
  MaterialTable t;
  ASSERT_TRUE(buildMaterialTable(c, 0, &t).isOk());
  ASSERT_EQ(t.layers.size(), 2u);       // White (material 1 has no base colour), image 0.
  ASSERT_EQ(t.data_layers.size(), 3u);  // Images 1, 2, 3.
  EXPECT_EQ(t.width, 4u);
  EXPECT_EQ(t.data_width, 8u);
  EXPECT_EQ(t.data_height, 2u);
  const MaterialEntry& e = t.materials[0];
  EXPECT_EQ(e.layer, 1u);
  EXPECT_EQ(e.emissive_layer, 1u);
  EXPECT_EQ(t.data_layers[e.normal_layer].rgba8[2], 255);
  EXPECT_EQ(t.data_layers[e.metallic_roughness_layer].rgba8[1], 200);
  EXPECT_EQ(t.data_layers[e.occlusion_layer].rgba8[0], 90);
  EXPECT_FLOAT_EQ(e.metallic, 0.3f);
  EXPECT_FLOAT_EQ(e.roughness, 0.7f);
  EXPECT_FLOAT_EQ(e.normal_scale, 0.5f);
  EXPECT_FLOAT_EQ(e.occlusion_strength, 0.25f);
  EXPECT_EQ(e.emissive_factor, glm::vec3(1.0f, 0.5f, 0.0f));
  EXPECT_FLOAT_EQ(e.alpha_cutoff, 0.4f);
  EXPECT_TRUE(e.double_sided);
  const MaterialEntry& plain = t.materials[1];
  EXPECT_EQ(plain.layer, 0u);
  EXPECT_EQ(plain.emissive_layer, kNoLayer);
  EXPECT_EQ(plain.normal_layer, kNoLayer);
  EXPECT_EQ(plain.metallic_roughness_layer, kNoLayer);
  EXPECT_EQ(plain.occlusion_layer, kNoLayer);
  EXPECT_LT(plain.alpha_cutoff, 0.0f);
  EXPECT_FALSE(plain.double_sided);
  // No data images: no data layers.
  c.materials.assign(1, Material{});
  ASSERT_TRUE(buildMaterialTable(c, 0, &t).isOk());
  EXPECT_TRUE(t.data_layers.empty());
}

TEST(MaterialTable, ResizeIsABoxWhenShrinkingAndBilinearWhenGrowing) {
  // A 4x1 ramp halved: each texel the average of two.
  Image ramp;
  ramp.width = 4;
  ramp.height = 1;
  ramp.rgba8 = {0, 0, 0, 0, 100, 10, 1, 255, 200, 20, 2, 255, 250, 30, 3, 255};
  const Image half = resizeImage(ramp, 2, 1);
  ASSERT_EQ(half.rgba8.size(), 8u);
  EXPECT_EQ(half.rgba8[0], 50);
  EXPECT_EQ(half.rgba8[4], 225);
  EXPECT_EQ(half.rgba8[7], 255);
  // Shrunk by a non-whole ratio (4 -> 3): weights 3/4 + 1/4 of the neighbours.
  const Image third = resizeImage(ramp, 3, 1);
  EXPECT_EQ(third.rgba8[0], 25);   // 0 * 0.75 + 100 * 0.25
  EXPECT_EQ(third.rgba8[4], 150);  // 100 * 0.5 + 200 * 0.5
  EXPECT_EQ(third.rgba8[8], 238);  // 200 * 0.25 + 250 * 0.75 = 237.5
  // Grown 2 -> 4 columns: bilinear between centres, clamped at the edges.
  Image two;
  two.width = 2;
  two.height = 1;
  two.rgba8 = {0, 0, 0, 0, 200, 200, 200, 200};
  const Image grown = resizeImage(two, 4, 2);
  ASSERT_EQ(grown.rgba8.size(), 32u);
  EXPECT_EQ(grown.rgba8[0], 0);     // Before the first centre: clamped.
  EXPECT_EQ(grown.rgba8[4], 50);    // x = 0.25 of the way.
  EXPECT_EQ(grown.rgba8[8], 150);
  EXPECT_EQ(grown.rgba8[12], 200);
  EXPECT_EQ(grown.rgba8[16 + 4], 50);  // The second row repeats the first.
  // The same size is a copy.
  EXPECT_EQ(resizeImage(ramp, 4, 1).rgba8, ramp.rgba8);
}

}  // namespace
}  // namespace si
