// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// What the glTF import keeps of a file's materials and surface (docs/gltf.md): the whole
// metallic-roughness material, tangents (the file's or generated for a normal map), vertex
// colours and second texture coordinates, out-of-range values clamped with a warning; on the
// generated patch of tests/gltf/pbr_asset.h.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "gltf/import_json.h"
#include "gltf/pbr_asset.h"
#include "si/gltf/gltf_import.h"

namespace si {
namespace {

using test::importJson;

TEST(GltfMaterials, TheWholeMetallicRoughnessMaterialIsImported) {
  test::PbrAssetDesc d;
  d.mask = true;
  d.double_sided = true;
  Character c;
  GltfImportReport r;
  const Status s = importJson(test::pbrAsset(d), &c, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  ASSERT_EQ(c.materials.size(), 2u);  // The default white one, then the file's.
  const Material& m = c.materials[1];
  EXPECT_EQ(m.name, "pbr");
  EXPECT_EQ(m.base_color_factor, glm::vec4(1.0f, 0.9f, 0.8f, 1.0f));
  EXPECT_FLOAT_EQ(m.metallic_factor, 0.25f);
  EXPECT_FLOAT_EQ(m.roughness_factor, 0.75f);
  EXPECT_FLOAT_EQ(m.normal_scale, 0.8f);
  EXPECT_FLOAT_EQ(m.occlusion_strength, 0.6f);
  EXPECT_EQ(m.emissive_factor, glm::vec3(0.2f, 0.1f, 0.05f));
  EXPECT_EQ(m.alpha_mode, AlphaMode::kMask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.5f);
  EXPECT_TRUE(m.double_sided);
  // Five distinct images, each decoded once, each the texture the file names.
  ASSERT_EQ(c.images.size(), 5u);
  EXPECT_EQ(r.images, 5u);
  const std::array<int32_t, 5> images = materialImages(m);
  for (size_t k = 0; k < images.size(); ++k) ASSERT_GE(images[k], 0) << k;
  const auto texel = [&](int32_t image, uint32_t x, uint32_t y) {
    const Image& img = c.images[size_t(image)];
    const uint8_t* p = &img.rgba8[(size_t(y) * img.width + x) * 4];
    return glm::u8vec4(p[0], p[1], p[2], p[3]);
  };
  EXPECT_EQ(texel(m.base_color_image, 0, 3), glm::u8vec4(200, 124, 60, 0));  // Masked half.
  EXPECT_EQ(texel(m.base_color_image, 15, 3).a, 255);
  EXPECT_EQ(texel(m.metallic_roughness_image, 15, 0), glm::u8vec4(0, 184, 255, 255));
  EXPECT_EQ(texel(m.occlusion_image, 0, 0).r, 128);
  EXPECT_EQ(texel(m.emissive_image, 1, 0).r, 255);
  const glm::u8vec4 n = texel(m.normal_image, 0, 0);  // Tilted towards +u.
  EXPECT_GT(n.r, 180);
  EXPECT_EQ(n.g, 128);
  // The file's tangents are kept.
  EXPECT_EQ(r.generated_tangents, 0u);
  ASSERT_EQ(c.mesh.tangents.size(), c.mesh.vertexCount());
  EXPECT_EQ(c.mesh.tangents[0], glm::vec4(1, 0, 0, 1));
  // Without images decoded: factors only.
  GltfImportDesc no_images;
  no_images.load_images = false;
  ASSERT_TRUE(importJson(test::pbrAsset(d), &c, &r, no_images).isOk());
  EXPECT_TRUE(c.images.empty());
  EXPECT_EQ(c.materials[1].normal_image, -1);
  EXPECT_FLOAT_EQ(c.materials[1].metallic_factor, 0.25f);
}

// COLOR_0 (normalized u8 RGB: alpha 1; float RGBA: out-of-range values clamped with a warning)
// and TEXCOORD_1 become the mesh's colours and second texture coordinates, vertex by vertex.
TEST(GltfMaterials, VertexColoursAndSecondTextureCoordinatesAreImported) {
  test::PbrAssetDesc d;
  d.colors = 3;
  d.texcoords1 = true;
  Character c;
  GltfImportReport r;
  Status s = importJson(test::pbrAsset(d), &c, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  ASSERT_EQ(c.mesh.colors.size(), c.mesh.vertexCount());
  ASSERT_EQ(c.mesh.texcoords1.size(), c.mesh.vertexCount());
  for (size_t v = 0; v < c.mesh.vertexCount(); ++v) {
    const glm::vec3& p = c.mesh.positions[v];
    const std::vector<uint8_t> rgb = test::pbrAssetColor(p.x, p.y);
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(c.mesh.colors[v][k], rgb[size_t(k)] / 255.0f) << v;
    EXPECT_EQ(c.mesh.colors[v].a, 1.0f);
    EXPECT_NEAR(c.mesh.texcoords1[v].x, 2.0f * p.y, 1e-6f) << v;
    EXPECT_NEAR(c.mesh.texcoords1[v].y, p.x + 0.5f, 1e-6f) << v;
  }
  d.colors = 4;
  d.texcoords1 = false;
  ASSERT_TRUE(importJson(test::pbrAsset(d), &c, &r).isOk());
  EXPECT_TRUE(c.mesh.texcoords1.empty());
  ASSERT_EQ(c.mesh.colors.size(), c.mesh.vertexCount());
  EXPECT_EQ(c.mesh.colors[0], glm::vec4(1.0f, 0.0f, 128 / 255.0f, 0.5f)) << "red 1.25 clamped";
  bool warned = false;
  for (const std::string& w : r.warnings)
    warned |= w.find("1 COLOR_0 values outside [0, 1] clamped") != std::string::npos;
  EXPECT_TRUE(warned);
  d.colors = 0;
  ASSERT_TRUE(importJson(test::pbrAsset(d), &c, &r).isOk());
  EXPECT_TRUE(c.mesh.colors.empty());
}

TEST(GltfMaterials, TangentsAreGeneratedForANormalMapWhenTheFileHasNone) {
  test::PbrAssetDesc d;
  d.tangents = false;
  Character c;
  GltfImportReport r;
  ASSERT_TRUE(importJson(test::pbrAsset(d), &c, &r).isOk());
  EXPECT_EQ(r.generated_tangents, c.mesh.vertexCount());
  EXPECT_EQ(r.degenerate_tangents, 0u);
  ASSERT_EQ(c.mesh.tangents.size(), c.mesh.vertexCount());
  // u grows along +x, v (glTF's, down the image) along -y: the file's own tangents (+x, w 1).
  for (const glm::vec4& t : c.mesh.tangents) {
    EXPECT_NEAR(t.x, 1.0f, 1e-5f);
    EXPECT_EQ(t.w, 1.0f);
  }
  bool warned = false;
  for (const std::string& w : r.warnings) warned |= w.find("no TANGENT") != std::string::npos;
  EXPECT_TRUE(warned);
  // No normal map: nothing generated, nothing stored.
  d.normal_map = false;
  ASSERT_TRUE(importJson(test::pbrAsset(d), &c, &r).isOk());
  EXPECT_EQ(r.generated_tangents, 0u);
  EXPECT_TRUE(c.mesh.tangents.empty());
}

TEST(GltfMaterials, OutOfRangeFactorsAndUnsupportedPartsAreClampedWithAWarning) {
  test::PbrAssetDesc d;
  std::string json = test::pbrAsset(d);
  const auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = json.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    json.replace(at, from.size(), to);
  };
  replace("\"metallicFactor\":0.25", "\"metallicFactor\":1.5");
  replace("\"emissiveTexture\":{\"index\":4}", "\"emissiveTexture\":{\"index\":9}");
  replace("\"occlusionTexture\":{\"index\":3,",
          "\"occlusionTexture\":{\"index\":3,\"texCoord\":1,");
  replace("\"name\":\"pbr\"}", "\"alphaMode\":\"BLEND\",\"name\":\"pbr\"}");
  Character c;
  GltfImportReport r;
  ASSERT_TRUE(importJson(json, &c, &r).isOk());
  const Material& m = c.materials[1];
  EXPECT_EQ(m.metallic_factor, 1.0f);
  EXPECT_EQ(m.emissive_image, -1);
  EXPECT_EQ(m.alpha_mode, AlphaMode::kBlend);
  std::string all;
  for (const std::string& w : r.warnings) all += w + "\n";
  for (const char* words : {"metallicFactor 1.5 is outside [0, 1]: 1 used",
                            "texture 9 does not exist", "TEXCOORD_1", "BLEND"})
    EXPECT_NE(all.find(words), std::string::npos) << words << " in\n" << all;
  EXPECT_TRUE(c.validate().isOk());
}

}  // namespace
}  // namespace si
