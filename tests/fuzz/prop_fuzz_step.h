// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd API fuzzer's props step (crowd_api_fuzz.cpp): hostile sockets and prop meshes
// attached to a copy of its character.

#include <string>
#include <vector>

#include "fuzz_input.h"
#include "si/core/prop.h"

namespace si::fuzz {

// makeSocket and attachProp with a hostile socket (any joint name, any offset) and mesh (counts,
// indices, materials and images sometimes out of range, values sometimes not finite): a refusal
// names why and leaves the character as it was; an attached prop adds one sub-mesh and its
// vertices, weighted 1 to the socket's joint, and the character still validates.
inline void attachFuzzedProp(const Character& base, Input& in, void (*fail)(const char*)) {
  Character c = base;
  const size_t vertices = c.mesh.vertexCount(), parts = c.mesh.sub_meshes.size();
  glm::mat4 offset(1.0f);
  for (int k = 0; k < 4; ++k) offset[3][k % 3] = in.f32();
  if (in.u8() < 32) offset[in.u8() % 4][in.u8() % 4] = in.f32();
  const char* names[] = {"j0", "j1", "j2", "nope"};
  Socket socket;
  Status s = makeSocket(c.skeleton, in.u8() & 1 ? "grip" : "", names[in.u8() % 4], offset, &socket);
  if (!s.isOk()) {
    if (s.message().empty()) fail("a refused makeSocket has no message");
    return;
  }
  PropMesh p;
  p.name = in.u8() & 1 ? "prop" : (in.u8() & 1 ? "body" : "");
  const size_t n = in.u8() % 9;
  for (size_t v = 0; v < n; ++v) {
    p.positions.push_back(glm::vec3(in.f32(), in.f32(), in.f32()));
    p.normals.push_back(glm::vec3(in.f32(), in.f32(), in.f32()));
    if (in.u8() & 1) p.texcoords.push_back(glm::vec2(in.f32(), in.f32()));
    if (in.u8() & 1) p.tangents.push_back(glm::vec4(in.f32(), in.f32(), in.f32(), 1.0f));
    if (in.u8() & 1) p.vertex_materials.push_back(uint16_t(in.u8() % 3));
  }
  const size_t indices = in.u8() % 13;
  for (size_t i = 0; i < indices; ++i) p.indices.push_back(in.u8() % 10);
  const size_t materials = in.u8() % 3;
  for (size_t m = 0; m < materials; ++m)
    p.materials.push_back(Material{"m", glm::vec4(1.0f), int32_t(in.u8() % 3) - 1});
  if (in.u8() & 1)
    p.images.push_back(Image{in.u8() % 3u, 1, std::vector<uint8_t>(4 * (in.u8() % 3u), 255)});
  uint32_t part = 0;
  s = attachProp(socket, p, &c, &part);
  if (!s.isOk()) {
    if (s.message().empty()) fail("a refused attachProp has no message");
    if (c.mesh.vertexCount() != vertices || c.mesh.sub_meshes.size() != parts)
      fail("a refused attachProp changed the character");
    return;
  }
  if (part != parts || c.mesh.sub_meshes.size() != parts + 1 ||
      c.mesh.vertexCount() != vertices + n || !c.validate().isOk())
    fail("an attached prop is not one more valid sub-mesh");
  for (size_t v = vertices; v < c.mesh.vertexCount(); ++v)
    if (c.mesh.joints[v][0] != socket.joint || c.mesh.weights[v][0] != 1.0f)
      fail("a prop vertex is not on its joint");
}

}  // namespace si::fuzz
