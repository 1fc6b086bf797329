// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Props from glTF (si/gltf/gltf_prop.h): a static mesh placed by its node hierarchy (T * R * S
// under a parent's translation; normals turned with it), its material; a mirroring node keeps
// the triangles' fronts outside; a skinned asset's mesh in its bind pose (CesiumMan: the
// character import's bind-pose bounds); refusals named.
#include "si/gltf/gltf_prop.h"

#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include "gltf/gltf_writer.h"
#include "test_assets.h"

namespace si {
namespace {

constexpr int kFloat = 5126, kUByte = 5121;

// One triangle (normals +Z, material 0, red) under a parent node at (1, 2, 3); the child turns
// 90 degrees about +Y and scales by (2, `sx`, 1).
std::string triangleFile(float sx = 1.0f, const char* children = "[1]") {
  test::GltfWriter w;
  const int pos = w.accessor(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}, kFloat, "VEC3", 3);
  const int nrm = w.accessor(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}, kFloat, "VEC3", 3);
  const int idx = w.accessor(std::vector<uint8_t>{0, 1, 2, 0}, kUByte, "SCALAR", 3);
  w.meshes =
      "{\"name\":\"blade\",\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(pos) +
      ",\"NORMAL\":" + std::to_string(nrm) + "},\"indices\":" + std::to_string(idx) +
      ",\"material\":0}]}";
  w.nodes =
      std::string("{\"name\":\"root\",\"translation\":[1,2,3],\"children\":") + children +
      "},{\"name\":\"blade\",\"mesh\":0,\"rotation\":[0,0.70710678,0,0.70710678],\"scale\":[2," +
      std::to_string(sx) + ",1]}";
  w.materials = "{\"name\":\"steel\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,0,0,1]}}";
  return w.json();
}

Status importString(const std::string& json, const GltfPropDesc& d, PropMesh* p,
                    GltfImportReport* r = nullptr) {
  return importGltfPropMemory(
      Span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()), "", d, p, r);
}

TEST(GltfProp, PlacesTheMeshByItsNodesAndKeepsItsMaterial) {
  PropMesh p;
  GltfImportReport report;
  ASSERT_TRUE(importString(triangleFile(), {}, &p, &report).isOk());
  EXPECT_EQ(p.name, "blade");
  ASSERT_EQ(p.positions.size(), 3u);
  // World = T(1, 2, 3) * R(90 deg about Y) * S(2, 1, 1): x -> 2 along -Z, y -> 1 along Y.
  const glm::dmat4 world =
      glm::translate(glm::dmat4(1.0), glm::dvec3(1, 2, 3)) *
      glm::mat4_cast(glm::angleAxis(glm::half_pi<double>(), glm::dvec3(0, 1, 0))) *
      glm::scale(glm::dmat4(1.0), glm::dvec3(2, 1, 1));
  const glm::vec3 local[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (size_t v = 0; v < 3; ++v) {
    EXPECT_LT(
        glm::length(glm::dvec3(p.positions[v]) - glm::dvec3(world * glm::dvec4(local[v], 1.0))),
        1e-6)
        << v;
    EXPECT_LT(glm::length(p.normals[v] - glm::vec3(1, 0, 0)), 1e-6f) << v;  // +Z turned to +X.
    EXPECT_EQ(p.vertex_materials[v], 1u);
  }
  ASSERT_EQ(p.materials.size(), 2u);  // The default white, then the file's.
  EXPECT_EQ(p.materials[1].name, "steel");
  EXPECT_EQ(p.materials[1].base_color_factor, glm::vec4(1, 0, 0, 1));
  EXPECT_TRUE(p.validate().isOk());
  // A name and a scale from the desc.
  GltfPropDesc d;
  d.name = "sword";
  d.scale = 0.5f;
  PropMesh half;
  ASSERT_TRUE(importString(triangleFile(), d, &half).isOk());
  EXPECT_EQ(half.name, "sword");
  EXPECT_EQ(half.positions[1], p.positions[1] * 0.5f);
}

TEST(GltfProp, AMirroringNodeKeepsFrontsOutside) {
  for (float sx : {1.0f, -1.0f}) {
    PropMesh p;
    ASSERT_TRUE(importString(triangleFile(sx), {}, &p).isOk());
    const glm::vec3 a = p.positions[p.indices[0]], b = p.positions[p.indices[1]],
                    c = p.positions[p.indices[2]];
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), p.normals[0]), 0.0f) << sx;
  }
}

// A skinned asset's mesh is taken in its bind pose: the character import's bind-pose bounds.
TEST(GltfProp, ASkinnedAssetIsItsBindPose) {
  const std::string path = test::assetPath("CesiumMan/glTF-Binary/CesiumMan.glb");
  ASSERT_TRUE(test::assetExists(path));
  PropMesh p;
  GltfImportReport report;
  ASSERT_TRUE(importGltfPropFile(path, {}, &p, &report).isOk());
  Character c;
  ASSERT_TRUE(importGltfFile(path, {}, &c, nullptr).isOk());
  const Aabb a = computeBounds(p.positions), b = c.bindPoseBounds();
  EXPECT_LT(glm::length(a.min - b.min), 1e-5f);
  EXPECT_LT(glm::length(a.max - b.max), 1e-5f);
  EXPECT_EQ(p.images.size(), c.images.size());
  EXPECT_EQ(p.materials.size(), c.materials.size());
}

TEST(GltfProp, RefusalsAreNamed) {
  PropMesh p;
  p.name = "kept";
  EXPECT_EQ(importString(triangleFile(), {}, nullptr).code(), StatusCode::kInvalidArgument);
  GltfPropDesc bad;
  bad.scale = 0.0f;
  EXPECT_EQ(importString(triangleFile(), bad, &p).code(), StatusCode::kInvalidArgument);
  bad.scale = std::nanf("");
  EXPECT_EQ(importString(triangleFile(), bad, &p).code(), StatusCode::kInvalidArgument);
  // The child names its parent: a cycle.
  std::string cyclic = triangleFile();
  const size_t at = cyclic.find("\"mesh\":0,");
  cyclic.insert(at, "\"children\":[0],");
  Status s = importString(cyclic, {}, &p);
  EXPECT_EQ(s.code(), StatusCode::kCorrupt);
  EXPECT_NE(s.message().find("not a tree"), std::string::npos) << s.message();
  // A child that does not exist.
  s = importString(triangleFile(1.0f, "[7]"), {}, &p);
  EXPECT_EQ(s.code(), StatusCode::kCorrupt);
  // No mesh under the scene's nodes.
  EXPECT_EQ(importString(triangleFile(1.0f, "[]"), {}, &p).code(), StatusCode::kUnsupported);
  EXPECT_EQ(importGltfPropFile("/no/such/file.glb", {}, &p, nullptr).code(), StatusCode::kIo);
  EXPECT_EQ(importString("{not json", {}, &p).code(), StatusCode::kCorrupt);
  EXPECT_EQ(p.name, "kept");
}

}  // namespace
}  // namespace si
