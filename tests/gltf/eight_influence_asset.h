// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A skinned file with 8 influences a vertex (JOINTS_1/WEIGHTS_1; issue "Any animated glTF
// becomes a crowd"), written by the tests, and its skinning evaluated here in double precision,
// independently of the library: where all 8 influences put a vertex, and where its 4 largest
// (renormalized) do.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gltf/gltf_writer.h"

namespace si::test {

// "root" holds 7 bones b1..b7, each 1 up; bone k turns about Z by k * 12 degrees over the
// clip "fan" (`duration` s, 1 by default; LINEAR). Vertices 0-2 have 8 influences each
// (kFanWeights, the largest on joint 3v, the next on 3v + 1, ... mod 8); vertex 3 only root's
// (JOINTS_1 weights zero).
struct EightInfluenceFan {
  static constexpr int kJoints = 8, kVertices = 4;
  static constexpr float kFanWeights[8] = {0.3f, 0.2f, 0.15f, 0.11f, 0.09f, 0.07f, 0.05f, 0.03f};
  std::vector<float> positions = {0.5f, 1.5f, 0.0f, -0.4f, 2.0f, 0.3f, 0.2f, 0.8f, -0.5f, 0, 0, 0};
  std::vector<float> key_rotations;  // Bone k's last key (x, y, z, w), as the file stores it.

  EightInfluenceFan() {
    for (int k = 1; k < kJoints; ++k) {
      const double half = 0.5 * k * 12.0 * 3.14159265358979323846 / 180.0;
      key_rotations.insert(key_rotations.end(),
                           {0.0f, 0.0f, float(std::sin(half)), float(std::cos(half))});
    }
  }
  float duration = 1.0f;
  bool second_set_zero = false;  // WEIGHTS_1 all zero (the first four then renormalized).

  // Joint of vertex v's influence slot i (of 8), and its weight.
  static int joint(int v, int i) { return v == 3 ? 0 : (i + 3 * v) % kJoints; }
  static float weight(int v, int i) { return v == 3 ? float(i == 0) : kFanWeights[i]; }

  std::string file() const {
    GltfWriter w;
    std::vector<uint8_t> j0, j1;
    std::vector<float> w0, w1;
    for (int v = 0; v < kVertices; ++v)
      for (int i = 0; i < 8; ++i) {
        (i < 4 ? j0 : j1).push_back(uint8_t(joint(v, i)));
        (i < 4 ? w0 : w1).push_back(i >= 4 && second_set_zero ? 0.0f : weight(v, i));
      }
    const int p = w.accessor(positions, 5126, "VEC3", kVertices,
                             ",\"min\":[-0.4,0,-0.5],\"max\":[0.5,2,0.3]");
    const int ja = w.accessor(j0, 5121, "VEC4", kVertices),
              jb = w.accessor(j1, 5121, "VEC4", kVertices);
    const int wa = w.accessor(w0, 5126, "VEC4", kVertices),
              wb = w.accessor(w1, 5126, "VEC4", kVertices);
    const int idx = w.accessor(std::vector<uint8_t>{0, 1, 2, 0, 2, 3}, 5121, "SCALAR", 6);
    w.meshes =
        "{\"name\":\"fan\",\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(p) +
        ",\"JOINTS_0\":" + std::to_string(ja) + ",\"WEIGHTS_0\":" + std::to_string(wa) +
        ",\"JOINTS_1\":" + std::to_string(jb) + ",\"WEIGHTS_1\":" + std::to_string(wb) +
        "},\"indices\":" + std::to_string(idx) + "}]}";
    std::vector<float> ibm;
    for (int k = 0; k < kJoints; ++k) {
      const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, k == 0 ? 0.0f : -1.0f, 0, 1};
      ibm.insert(ibm.end(), m, m + 16);
    }
    const int ibm_acc = w.accessor(ibm, 5126, "MAT4", kJoints);
    w.nodes = "{\"name\":\"root\",\"children\":[1,2,3,4,5,6,7]}";
    for (int k = 1; k < kJoints; ++k)
      w.nodes += ",{\"name\":\"b" + std::to_string(k) + "\",\"translation\":[0,1,0]}";
    w.nodes += ",{\"name\":\"body\",\"mesh\":0,\"skin\":0}";
    w.skins =
        "{\"joints\":[0,1,2,3,4,5,6,7],\"inverseBindMatrices\":" + std::to_string(ibm_acc) + "}";
    const int times = w.accessor(std::vector<float>{0.0f, duration}, 5126, "SCALAR", 2,
                                 ",\"min\":[0],\"max\":[" + std::to_string(duration) + "]");
    std::string samplers, channels;
    for (int k = 1; k < kJoints; ++k) {
      const float* q = &key_rotations[size_t(k - 1) * 4];
      const std::vector<float> keys = {0, 0, 0, 1, q[0], q[1], q[2], q[3]};
      const int out = w.accessor(keys, 5126, "VEC4", 2);
      samplers += std::string(k > 1 ? "," : "") + "{\"input\":" + std::to_string(times) +
                  ",\"output\":" + std::to_string(out) + "}";
      channels += std::string(k > 1 ? "," : "") + "{\"sampler\":" + std::to_string(k - 1) +
                  ",\"target\":{\"node\":" + std::to_string(k) + ",\"path\":\"rotation\"}}";
    }
    w.animations =
        "{\"name\":\"fan\",\"samplers\":[" + samplers + "],\"channels\":[" + channels + "]}";
    return w.json();
  }

  // Joint k's skinning matrix at the clip's fraction t (rest at t = 0): the slerp from the
  // identity to the stored key turns about Z by t times the key's angle; 1 up, turned, 1 down.
  glm::dmat4 skinning(int k, double t) const {
    if (k == 0) return glm::dmat4(1.0);
    const float* q = &key_rotations[size_t(k - 1) * 4];
    const double angle = t * 2.0 * std::atan2(double(q[2]), double(q[3]));
    glm::dmat4 r(1.0);
    r[0][0] = r[1][1] = std::cos(angle);
    r[0][1] = std::sin(angle);
    r[1][0] = -std::sin(angle);
    glm::dmat4 up(1.0), down(1.0);
    up[3][1] = 1.0;
    down[3][1] = -1.0;
    return up * r * down;
  }

  // Where vertex v's influences put it at the clip's fraction t: all 8, or the 4 largest
  // renormalized.
  glm::dvec3 skinned(int v, double t, bool largest_four) const {
    const glm::dvec4 p(positions[size_t(v) * 3], positions[size_t(v) * 3 + 1],
                       positions[size_t(v) * 3 + 2], 1.0);
    double total = 0.0;
    for (int i = 0; i < (largest_four ? 4 : 8); ++i) total += weight(v, i);
    glm::dvec3 out(0.0);
    for (int i = 0; i < (largest_four ? 4 : 8); ++i)
      out += double(weight(v, i)) / total * glm::dvec3(skinning(joint(v, i), t) * p);
    return out;
  }
};

}  // namespace si::test
