// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A file animated by its nodes, no skin (issue "Any animated glTF becomes a crowd"), written by
// the tests, and its node graph evaluated here in double precision, independently of the
// library: what tests/gltf/gltf_node_animation_test.cpp and the render tests check against.

#include <cmath>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "gltf/gltf_writer.h"

namespace si::test {

inline constexpr int kGltfFloat = 5126, kGltfUByte = 5121;
inline constexpr double kPi = 3.14159265358979323846;

inline std::string gltfNumber(double v) {
  return std::to_string(v);
}

// A triangle mesh (positions and normals) named `name`.
inline std::string triangleMesh(GltfWriter* w, const char* name, const std::vector<float>& pos,
                                const std::vector<float>& normals) {
  const int p = w->accessor(pos, kGltfFloat, "VEC3", 3, ",\"min\":[-1,-1,-1],\"max\":[1,1,1]");
  const int n = w->accessor(normals, kGltfFloat, "VEC3", 3);
  return std::string("{\"name\":\"") + name +
         "\",\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(p) +
         ",\"NORMAL\":" + std::to_string(n) + "}}]}";
}

// An animation `name` of one channel: node `node`'s `path` ("rotation", "translation",
// "scale") from the first to the second value of `values` (VEC4 for a rotation, else VEC3)
// over keys at 0 and 1 s, LINEAR.
inline std::string oneChannelAnimation(GltfWriter* w, const char* name, int node, const char* path,
                                       const std::vector<float>& values) {
  const int times = w->accessor(std::vector<float>{0.0f, 1.0f}, kGltfFloat, "SCALAR", 2);
  const bool rotation = std::string(path) == "rotation";
  const int out = w->accessor(values, kGltfFloat, rotation ? "VEC4" : "VEC3", 2);
  return std::string("{\"name\":\"") + name +
         "\",\"samplers\":[{\"input\":" + std::to_string(times) +
         ",\"output\":" + std::to_string(out) +
         "}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":" + std::to_string(node) +
         ",\"path\":\"" + path + "\"}}]}";
}

// The plate (facing +Y) and the stick (facing +Z), in their nodes' spaces.
inline const std::vector<float> kPlate = {0, 0, 0, 0, 0, 1, 1, 0, 0};
inline const std::vector<float> kStick = {0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0};

// "rig" holds "base" (the plate, turning 90 degrees about Y over a second), which holds "arm"
// (the stick at twice its size, rising from 1 to 2 above the base), and "static" (the plate,
// moved, turned 45 degrees about Z and mirrored in Z). No skin.
inline std::string nodeAnimatedFile() {
  GltfWriter w;
  w.meshes = triangleMesh(&w, "plate", kPlate, {0, 1, 0, 0, 1, 0, 0, 1, 0}) + "," +
             triangleMesh(&w, "stick", kStick, {0, 0, 1, 0, 0, 1, 0, 0, 1});
  const double s45 = std::sin(kPi / 8), c45 = std::cos(kPi / 8);
  w.nodes =
      "{\"name\":\"rig\",\"children\":[1,3]},"
      "{\"name\":\"base\",\"mesh\":0,\"children\":[2]},"
      "{\"name\":\"arm\",\"mesh\":1,\"translation\":[0,1,0],\"scale\":[2,2,2]},"
      "{\"name\":\"static\",\"mesh\":0,\"translation\":[3,0,0],\"rotation\":[0,0," +
      gltfNumber(s45) + "," + gltfNumber(c45) + "],\"scale\":[1,1,-1]}";
  const int times = w.accessor(std::vector<float>{0.0f, 1.0f}, kGltfFloat, "SCALAR", 2,
                               ",\"min\":[0],\"max\":[1]");
  const float r = float(std::sqrt(0.5));
  const int turns = w.accessor(std::vector<float>{0, 0, 0, 1, 0, r, 0, r}, kGltfFloat, "VEC4", 2);
  const int rises = w.accessor(std::vector<float>{0, 1, 0, 0, 2, 0}, kGltfFloat, "VEC3", 2);
  w.animations = "{\"name\":\"move\",\"samplers\":[{\"input\":" + std::to_string(times) +
                 ",\"output\":" + std::to_string(turns) + "},{\"input\":" + std::to_string(times) +
                 ",\"output\":" + std::to_string(rises) +
                 "}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,\"path\":\"rotation\"}},"
                 "{\"sampler\":1,\"target\":{\"node\":2,\"path\":\"translation\"}}]}";
  return w.json();
}

// The node graph of nodeAnimatedFile() at time t, evaluated here: each mesh vertex in the
// scene, in the order the file lists the nodes (base, arm, static).
inline std::vector<glm::dvec3> expectedPositions(double t) {
  const glm::dmat4 base = glm::rotate(glm::dmat4(1.0), 0.5 * kPi * t, glm::dvec3(0, 1, 0));
  const glm::dmat4 arm = base * glm::translate(glm::dmat4(1.0), glm::dvec3(0, 1.0 + t, 0)) *
                         glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
  const glm::dmat4 fixed = glm::translate(glm::dmat4(1.0), glm::dvec3(3, 0, 0)) *
                           glm::rotate(glm::dmat4(1.0), 0.25 * kPi, glm::dvec3(0, 0, 1)) *
                           glm::scale(glm::dmat4(1.0), glm::dvec3(1, 1, -1));
  std::vector<glm::dvec3> out;
  const auto add = [&](const glm::dmat4& m, const std::vector<float>& local) {
    for (size_t v = 0; v < local.size(); v += 3)
      out.push_back(glm::dvec3(m * glm::dvec4(local[v], local[v + 1], local[v + 2], 1.0)));
  };
  add(base, kPlate);
  add(arm, kStick);
  add(fixed, kPlate);
  return out;
}

}  // namespace si::test
