// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A generated asset with a whole glTF metallic-roughness material: a 1 x 1 patch of
// cells x cells quads on z = 0 (x in [-0.5, 0.5], y in [0, 1], facing +z), skinned to a root
// and a child joint at y = 0.5 (weights blending over the middle third), the child turning
// about z and y in its one clip "turn" (1 s); TEXCOORD_0 = (x + 0.5, 1 - y). Its material
// uses five textures (PNG data URIs): a base colour, a metallic-roughness, a normal, an
// occlusion and an emissive one. The glTF import tests (what is read) and the render tests
// (normal-mapped lighting against a CPU reference, alpha-masked parts) share it.

#include <cmath>
#include <string>
#include <vector>

#include "gltf/gltf_writer.h"

namespace si::test {

struct PbrAssetDesc {
  int cells = 8;
  bool tangents = true;  ///< TANGENT in the file (+x, w = 1); otherwise the import makes them.
  float bitangent_sign = 1.0f;  ///< The file's TANGENT w (-1: the bitangent is -v).
  bool mask = false;     ///< alphaMode MASK (cutoff 0.5); the base colour alpha's left half 0.
  bool double_sided = false;
  bool normal_map = true;
  uint32_t texture_size = 16;
  /// COLOR_0: 0 none; 3 RGB normalized u8, pbrAssetColor(); 4 RGBA float, pbrAssetColor() with
  /// alpha 0.5 except a red of 1.25 at vertex 0 (out of range: the import clamps it).
  int colors = 0;
  bool texcoords1 = false;  ///< TEXCOORD_1 = (2 y, x + 0.5), float.
};

/// COLOR_0 at (x, y) as 3: (x + 0.5, y, 0.5) in 8 bits.
inline std::vector<uint8_t> pbrAssetColor(float x, float y) {
  return {uint8_t(std::lround((x + 0.5f) * 255.0f)), uint8_t(std::lround(y * 255.0f)), 128};
}

/// The normal map's tangent-space normal at texel (x, y) of a size x size map: tilted 35
/// degrees towards +u in even columns of 4 texels and towards +v in odd ones.
inline std::vector<float> pbrAssetNormal(uint32_t x, uint32_t y) {
  (void)y;
  const float s = std::sin(0.61086524f), c = std::cos(0.61086524f);
  return (x / 4) % 2 == 0 ? std::vector<float>{s, 0, c} : std::vector<float>{0, s, c};
}

inline std::string pbrAsset(const PbrAssetDesc& d) {
  constexpr int kFloat = 5126, kUByte = 5121, kUShort = 5123;
  GltfWriter w;
  std::vector<float> pos, nrm, tan, uv, uv1, weights, rgba;
  std::vector<uint8_t> joints, rgb;
  std::vector<uint16_t> idx;
  const int n = d.cells;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = float(i) / n - 0.5f, y = float(j) / n;
      pos.insert(pos.end(), {x, y, 0});
      nrm.insert(nrm.end(), {0, 0, 1});
      tan.insert(tan.end(), {1, 0, 0, d.bitangent_sign});
      uv.insert(uv.end(), {x + 0.5f, 1.0f - y});
      uv1.insert(uv1.end(), {2.0f * y, x + 0.5f});
      const std::vector<uint8_t> c = pbrAssetColor(x, y);
      rgb.insert(rgb.end(), c.begin(), c.end());
      rgba.insert(rgba.end(),
                  {pos.size() == 3 ? 1.25f : c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, 0.5f});
      const float child = std::fmin(std::fmax((y - 1.0f / 3.0f) * 3.0f, 0.0f), 1.0f);
      joints.insert(joints.end(), {0, 1, 0, 0});
      weights.insert(weights.end(), {1.0f - child, child, 0, 0});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto at = [&](int a, int b) { return uint16_t(b * (n + 1) + a); };
      idx.insert(idx.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1),
                             at(i, j + 1)});
    }
  const size_t nv = pos.size() / 3;
  std::string attributes =
      "\"POSITION\":" + std::to_string(w.accessor(pos, kFloat, "VEC3", nv, ",\"min\":[-0.5,0,0],\"max\":[0.5,1,0]")) +
      ",\"NORMAL\":" + std::to_string(w.accessor(nrm, kFloat, "VEC3", nv)) +
      ",\"TEXCOORD_0\":" + std::to_string(w.accessor(uv, kFloat, "VEC2", nv)) +
      ",\"JOINTS_0\":" + std::to_string(w.accessor(joints, kUByte, "VEC4", nv)) +
      ",\"WEIGHTS_0\":" + std::to_string(w.accessor(weights, kFloat, "VEC4", nv));
  if (d.tangents) attributes += ",\"TANGENT\":" + std::to_string(w.accessor(tan, kFloat, "VEC4", nv));
  if (d.texcoords1)
    attributes += ",\"TEXCOORD_1\":" + std::to_string(w.accessor(uv1, kFloat, "VEC2", nv));
  if (d.colors == 3)
    attributes += ",\"COLOR_0\":" +
                  std::to_string(w.accessor(rgb, kUByte, "VEC3", nv, ",\"normalized\":true"));
  if (d.colors == 4)
    attributes += ",\"COLOR_0\":" + std::to_string(w.accessor(rgba, kFloat, "VEC4", nv));
  const int a_idx = w.accessor(idx, kUShort, "SCALAR", idx.size());
  w.meshes = "{\"name\":\"patch\",\"primitives\":[{\"attributes\":{" + attributes +
             "},\"indices\":" + std::to_string(a_idx) + ",\"material\":0}]}";
  w.nodes = "{\"name\":\"root\",\"children\":[1,2]},{\"name\":\"child\",\"translation\":[0,0.5,0]},"
            "{\"name\":\"patch\",\"mesh\":0,\"skin\":0}";
  w.skins = "{\"name\":\"main\",\"joints\":[0,1]}";
  const int in = w.accessor(std::vector<float>{0.0f, 1.0f}, kFloat, "SCALAR", 2);
  // 40 degrees about z, then 25 about y: the tangent frame turns out of the plane.
  const int out = w.accessor(std::vector<float>{0, 0, 0, 1, 0.0740f, 0.2035f, 0.3311f, 0.9185f},
                             kFloat, "VEC4", 2);
  w.animations = "{\"name\":\"turn\",\"samplers\":[{\"input\":" + std::to_string(in) +
                 ",\"output\":" + std::to_string(out) +
                 "}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,\"path\":\"rotation\"}}]}";
  // Textures: 0 base colour, 1 metallic-roughness, 2 normal, 3 occlusion, 4 emissive.
  const uint32_t s = d.texture_size;
  std::vector<uint8_t> base, mr, normal, occlusion, emissive;
  for (uint32_t y = 0; y < s; ++y)
    for (uint32_t x = 0; x < s; ++x) {
      const uint8_t alpha = d.mask ? (x < s / 2 ? 0 : 255) : 255;
      base.insert(base.end(), {200, uint8_t(100 + 8 * (y % 8)), 60, alpha});
      mr.insert(mr.end(), {0, uint8_t(64 + 8 * x), uint8_t(x < s / 2 ? 0 : 255), 255});
      const std::vector<float> t = pbrAssetNormal(x, y);
      normal.insert(normal.end(), {uint8_t(std::lround((t[0] * 0.5f + 0.5f) * 255.0f)),
                                   uint8_t(std::lround((t[1] * 0.5f + 0.5f) * 255.0f)),
                                   uint8_t(std::lround((t[2] * 0.5f + 0.5f) * 255.0f)), 255});
      occlusion.insert(occlusion.end(), {uint8_t(y < s / 2 ? 128 : 255), 0, 0, 255});
      emissive.insert(emissive.end(), {uint8_t(x % 2 ? 255 : 0), 0, 0, 255});
    }
  w.images = GltfWriter::pngImage(s, s, base) + "," + GltfWriter::pngImage(s, s, mr) + "," +
             GltfWriter::pngImage(s, s, normal) + "," + GltfWriter::pngImage(s, s, occlusion) +
             "," + GltfWriter::pngImage(s, s, emissive);
  w.textures = "{\"source\":0},{\"source\":1},{\"source\":2},{\"source\":3},{\"source\":4}";
  w.materials = std::string("{\"name\":\"pbr\",\"pbrMetallicRoughness\":{") +
                "\"baseColorFactor\":[1,0.9,0.8,1],\"baseColorTexture\":{\"index\":0},"
                "\"metallicFactor\":0.25,\"roughnessFactor\":0.75,"
                "\"metallicRoughnessTexture\":{\"index\":1}}," +
                (d.normal_map ? "\"normalTexture\":{\"index\":2,\"scale\":0.8}," : "") +
                "\"occlusionTexture\":{\"index\":3,\"strength\":0.6},"
                "\"emissiveTexture\":{\"index\":4},\"emissiveFactor\":[0.2,0.1,0.05]," +
                (d.mask ? "\"alphaMode\":\"MASK\",\"alphaCutoff\":0.5," : "") +
                (d.double_sided ? "\"doubleSided\":true," : "") + "\"name\":\"pbr\"}";
  return w.json();
}

}  // namespace si::test
