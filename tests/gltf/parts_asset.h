// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A generated production-style asset: one skin of two joints (a root and a bending child),
// meshes of many primitives (each a small quad of its own material, rigidly bound to one
// joint), optional "_LOD1" levels, one animation. The glTF import tests (parts and variation
// groups) and the render tests (every part drawn with its material) share it.

#include <string>
#include <vector>

#include "gltf/gltf_writer.h"

namespace si::test {

struct PartsMesh {
  std::string name;
  uint32_t primitives = 1;
  bool lod1 = false;  ///< Also a "<name>_LOD1" mesh: the same primitives as one triangle each.
};

/// The asset's glTF JSON. Primitive k (counting through the meshes in order) is a quad of side
/// 0.08 at column k % 20, row k / 20 (0.1 apart, facing +z), bound to joint k % 2, with
/// material k % material_count (each a distinct base colour factor).
inline std::string partsAsset(const std::vector<PartsMesh>& meshes, uint32_t material_count) {
  constexpr int kFloat = 5126, kUByte = 5121, kUShort = 5123;
  GltfWriter w;
  std::string mesh_json, node_json, node_list;
  uint32_t k = 0, mesh_index = 0;
  const auto addMesh = [&](const std::string& name, uint32_t first, uint32_t count, bool lod) {
    std::string prims;
    for (uint32_t i = 0; i < count; ++i) {
      const uint32_t n = first + i;
      const float x = float(n % 20) * 0.1f - 1.0f, y = float(n / 20) * 0.1f, s = 0.08f;
      const std::vector<float> pos = {x, y, 0, x + s, y, 0, x + s, y + s, 0, x, y + s, 0};
      const std::vector<float> nrm = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
      const uint8_t j = uint8_t(n % 2);
      const std::vector<uint8_t> joints = {j, 0, 0, 0, j, 0, 0, 0, j, 0, 0, 0, j, 0, 0, 0};
      const std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
      const std::vector<uint16_t> idx = lod ? std::vector<uint16_t>{0, 1, 2, 0}
                                            : std::vector<uint16_t>{0, 1, 2, 0, 2, 3};
      const int a_pos = w.accessor(pos, kFloat, "VEC3", 4,
                                   ",\"min\":[" + std::to_string(x) + "," + std::to_string(y) +
                                       ",0],\"max\":[" + std::to_string(x + s) + "," +
                                       std::to_string(y + s) + ",0]");
      const int a_nrm = w.accessor(nrm, kFloat, "VEC3", 4);
      const int a_j = w.accessor(joints, kUByte, "VEC4", 4);
      const int a_w = w.accessor(weights, kFloat, "VEC4", 4);
      const int a_i = w.accessor(idx, kUShort, "SCALAR", lod ? 3 : 6);
      prims += std::string(i ? "," : "") + "{\"attributes\":{\"POSITION\":" +
               std::to_string(a_pos) + ",\"NORMAL\":" + std::to_string(a_nrm) +
               ",\"JOINTS_0\":" + std::to_string(a_j) + ",\"WEIGHTS_0\":" + std::to_string(a_w) +
               "},\"indices\":" + std::to_string(a_i) +
               ",\"material\":" + std::to_string(n % material_count) + "}";
    }
    mesh_json += std::string(mesh_index ? "," : "") + "{\"name\":\"" + name +
                 "\",\"primitives\":[" + prims + "]}";
    node_json += ",{\"name\":\"" + name + "_node\",\"mesh\":" + std::to_string(mesh_index) +
                 ",\"skin\":0}";
    node_list += "," + std::to_string(2 + mesh_index);
    ++mesh_index;
  };
  for (const PartsMesh& m : meshes) {
    addMesh(m.name, k, m.primitives, false);
    if (m.lod1) addMesh(m.name + "_LOD1", k, m.primitives, true);
    k += m.primitives;
  }
  for (uint32_t i = 0; i < material_count; ++i) {
    const float r = float(i % 5) / 4.0f, g = float((i / 5) % 5) / 4.0f, b = float(i / 25 % 4) / 3.0f;
    w.materials += std::string(i ? "," : "") + "{\"name\":\"m" + std::to_string(i) +
                   "\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[" + std::to_string(r) + "," +
                   std::to_string(g) + "," + std::to_string(b) + ",1]}}";
  }
  w.meshes = mesh_json;
  w.nodes = "{\"name\":\"root\",\"children\":[1" + node_list + "]},"
            "{\"name\":\"child\",\"translation\":[0,1,0]}" + node_json;
  w.skins = "{\"name\":\"main\",\"joints\":[0,1]}";
  const int in = w.accessor(std::vector<float>{0.0f, 0.5f, 1.0f}, kFloat, "SCALAR", 3);
  const int out = w.accessor(std::vector<float>{0, 0, 0, 1, 0, 0, 0.2588190f, 0.9659258f, 0, 0, 0, 1},
                             kFloat, "VEC4", 3);
  w.animations = "{\"name\":\"sway\",\"samplers\":[{\"input\":" + std::to_string(in) +
                 ",\"output\":" + std::to_string(out) +
                 "}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,\"path\":\"rotation\"}}]}";
  return w.json();
}

}  // namespace si::test
