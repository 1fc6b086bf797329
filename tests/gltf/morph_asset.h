// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A file animated by morph target weights, written by the tests (the shape of Khronos'
// AnimatedMorphCube: a mesh on a node, no skin, one weights channel), and its morphs evaluated
// here in double precision, independently of the library: what
// tests/gltf/gltf_morph_targets_test.cpp checks the import and the reference against.

#include <cmath>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "gltf/gltf_writer.h"
#include "gltf/node_animated_asset.h"

namespace si::test {

// The quad in z = 0 (facing +Z, tangent +X), as triangles 0 1 2 and 0 2 3.
inline const std::vector<float> kMorphQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
inline const std::vector<float> kMorphQuadNormals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
inline const std::vector<float> kMorphQuadTangents = {1, 0, 0, 1, 1, 0, 0, 1,
                                                      1, 0, 0, 1, 1, 0, 0, 1};
// Three targets, dense as glTF stores them: "raise" lifts the top edge out of the plane and
// tips its normals; "widen" moves the right edge and turns vertex 1's tangent; "blink" pushes
// vertex 0 back. Vertex-major, 4 vertices of 3 floats each.
inline const std::vector<float> kRaisePositions = {0, 0, 0, 0, 0, 0, 0, 0, 0.5f, 0, 0, 0.5f};
inline const std::vector<float> kRaiseNormals = {0, 0, 0, 0, 0, 0, 0, -0.5f, 0, 0, -0.5f, 0};
inline const std::vector<float> kWidenPositions = {0, 0, 0, 0.5f, 0, 0, 0.5f, 0, 0, 0, 0, 0};
inline const std::vector<float> kWidenTangents = {0, 0, 0, 0, 0.25f, 0, 0, 0, 0, 0, 0, 0};
inline const std::vector<float> kBlinkPositions = {0, 0, -0.25f, 0, 0, 0, 0, 0, 0, 0, 0, 0};
// The mesh's default weights, and the weights channel's keys at 0, 1 and 2 s.
inline const std::vector<float> kMorphDefaults = {0.0f, 0.0f, 0.75f};
inline const std::vector<float> kMorphKeyTimes = {0.0f, 1.0f, 2.0f};
inline const std::vector<float> kMorphKeyWeights = {0.0f, 0.0f,  0.2f, 1.0f, 0.5f,
                                                    0.0f, 0.25f, 1.0f, 1.0f};
// CUBICSPLINE's in- and out-tangents per key (per second, as glTF stores them).
inline const std::vector<float> kMorphInTangents = {0.3f,  -0.2f, 0.1f, 0.0f, 1.0f,
                                                    -0.5f, -2.0f, 0.5f, 0.0f};
inline const std::vector<float> kMorphOutTangents = {1.5f, 0.0f, -0.4f, -1.0f, 0.25f,
                                                     0.5f, 0.0f, 0.0f,  0.0f};

// The node "face": translated, turned 90 degrees about Y and scaled by 2, so the import must
// move the deltas as it moves the surface.
inline glm::dmat4 morphNodeMatrix() {
  return glm::translate(glm::dmat4(1.0), glm::dvec3(1, 2, 3)) *
         glm::rotate(glm::dmat4(1.0), 0.5 * kPi, glm::dvec3(0, 1, 0)) *
         glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
}

// The file: node "face" with the quad and its three targets (names in extras.targetNames),
// animation "morph" (one weights channel, `interpolation`: LINEAR, STEP or CUBICSPLINE) and
// "still" (the node's translation held: the default weights apply). `mesh_weights` is the
// mesh's "weights" array (the default weights; the tests give wrong ones too).
inline std::string morphFile(const std::string& interpolation,
                             const std::string& mesh_weights = "[0,0,0.75]") {
  GltfWriter w;
  const auto vec3 = [&](const std::vector<float>& v) {
    return std::to_string(w.accessor(v, kGltfFloat, "VEC3", 4));
  };
  const int pos = w.accessor(kMorphQuad, kGltfFloat, "VEC3", 4, ",\"min\":[0,0,0],\"max\":[1,1,0]");
  const int nrm = w.accessor(kMorphQuadNormals, kGltfFloat, "VEC3", 4);
  const int tan = w.accessor(kMorphQuadTangents, kGltfFloat, "VEC4", 4);
  const int idx = w.accessor(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, 5123, "SCALAR", 6);
  w.meshes =
      "{\"name\":\"face\",\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(pos) +
      ",\"NORMAL\":" + std::to_string(nrm) + ",\"TANGENT\":" + std::to_string(tan) +
      "},\"indices\":" + std::to_string(idx) +
      ",\"targets\":[{\"POSITION\":" + vec3(kRaisePositions) +
      ",\"NORMAL\":" + vec3(kRaiseNormals) + "},{\"POSITION\":" + vec3(kWidenPositions) +
      ",\"TANGENT\":" + vec3(kWidenTangents) + "},{\"POSITION\":" + vec3(kBlinkPositions) +
      "}]}],\"weights\":" + mesh_weights +
      ",\"extras\":{\"targetNames\":[\"raise\",\"widen\",\"blink\"]}}";
  const double s = std::sin(kPi / 4), c = std::cos(kPi / 4);
  w.nodes = "{\"name\":\"face\",\"mesh\":0,\"translation\":[1,2,3],\"rotation\":[0," +
            gltfNumber(s) + ",0," + gltfNumber(c) + "],\"scale\":[2,2,2]}";
  const int times = w.accessor(kMorphKeyTimes, kGltfFloat, "SCALAR", 3, ",\"min\":[0],\"max\":[2]");
  std::vector<float> out;
  if (interpolation == "CUBICSPLINE") {
    for (size_t k = 0; k < 3; ++k)
      for (const std::vector<float>* run :
           {&kMorphInTangents, &kMorphKeyWeights, &kMorphOutTangents})
        out.insert(out.end(), run->begin() + ptrdiff_t(k * 3), run->begin() + ptrdiff_t(k * 3 + 3));
  } else {
    out = kMorphKeyWeights;
  }
  const int weights = w.accessor(out, kGltfFloat, "SCALAR", out.size());
  const int still_times = w.accessor(std::vector<float>{0.0f, 1.0f}, kGltfFloat, "SCALAR", 2);
  const int still = w.accessor(std::vector<float>{1, 2, 3, 1, 2, 3}, kGltfFloat, "VEC3", 2);
  w.animations =
      "{\"name\":\"morph\",\"samplers\":[{\"input\":" + std::to_string(times) +
      ",\"output\":" + std::to_string(weights) + ",\"interpolation\":\"" + interpolation +
      "\"}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"weights\"}}]},"
      "{\"name\":\"still\",\"samplers\":[{\"input\":" +
      std::to_string(still_times) + ",\"output\":" + std::to_string(still) +
      "}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"translation\"}}]}";
  return w.json();
}

// Target k's weight of the "morph" animation at time t (clamped to the keys), evaluated here
// as glTF's "Interpolation" appendix says.
inline double expectedMorphWeight(const std::string& interpolation, size_t k, double t) {
  const auto key = [&](size_t i) { return double(kMorphKeyWeights[i * 3 + k]); };
  if (t <= 0.0) return key(0);
  if (t >= 2.0) return key(2);
  const size_t a = t < 1.0 ? 0 : 1;
  const double u = t - double(a);  // Keys 1 s apart.
  if (interpolation == "STEP") return key(a);
  if (interpolation == "LINEAR") return key(a) * (1.0 - u) + key(a + 1) * u;
  const double m0 = kMorphOutTangents[a * 3 + k], m1 = kMorphInTangents[(a + 1) * 3 + k];
  return (2 * u * u * u - 3 * u * u + 1) * key(a) + (u * u * u - 2 * u * u + u) * m0 +
         (-2 * u * u * u + 3 * u * u) * key(a + 1) + (u * u * u - u * u) * m1;
}

// The quad's vertices, normals and tangents (xyz) at `weights`, placed by the node, in
// double: p' = M (p + sum w d), n' = normalize(N (n + sum w dn)), t' = normalize(L (t + sum w dt)).
struct ExpectedMorph {
  std::vector<glm::dvec3> positions, normals, tangents;
};
inline ExpectedMorph expectedMorph(const std::vector<double>& weights) {
  const glm::dmat4 m = morphNodeMatrix();
  const glm::dmat3 linear(m), normal_matrix = glm::transpose(glm::inverse(glm::dmat3(m)));
  const auto at = [](const std::vector<float>& v, size_t i) {
    return glm::dvec3(v[i * 3], v[i * 3 + 1], v[i * 3 + 2]);
  };
  const std::vector<float> zero(12, 0.0f);
  const std::vector<float>* dp[3] = {&kRaisePositions, &kWidenPositions, &kBlinkPositions};
  const std::vector<float>* dn[3] = {&kRaiseNormals, &zero, &zero};
  const std::vector<float>* dt[3] = {&zero, &kWidenTangents, &zero};
  ExpectedMorph out;
  for (size_t v = 0; v < 4; ++v) {
    glm::dvec3 p = at(kMorphQuad, v), n = at(kMorphQuadNormals, v);
    glm::dvec3 t(kMorphQuadTangents[v * 4], kMorphQuadTangents[v * 4 + 1],
                 kMorphQuadTangents[v * 4 + 2]);
    for (size_t k = 0; k < 3; ++k) {
      p += weights[k] * at(*dp[k], v);
      n += weights[k] * at(*dn[k], v);
      t += weights[k] * at(*dt[k], v);
    }
    out.positions.push_back(glm::dvec3(m * glm::dvec4(p, 1.0)));
    out.normals.push_back(glm::normalize(normal_matrix * n));
    out.tangents.push_back(glm::normalize(linear * t));
  }
  return out;
}

}  // namespace si::test
