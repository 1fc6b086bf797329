// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A prop for the sockets-and-props tests (core, crowd, render): a box held at the right hand.

#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "si/core/prop.h"

namespace si::test {

// A box of half extents `h` with its centre at z = h.z (a blade along +Z from the grip), two
// materials (the far half's triangles the second), 24 vertices with face normals.
inline PropMesh boxProp(const glm::vec3& h) {
  PropMesh p;
  p.name = "box";
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      glm::vec3 n(0.0f);
      n[axis] = sign;
      const glm::vec3 u = glm::vec3(n.y, n.z, n.x), v = glm::cross(n, u);
      const uint32_t first = uint32_t(p.positions.size());
      for (const glm::vec2 c :
           {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
        p.positions.push_back((n + c.x * u + c.y * v) * h + glm::vec3(0, 0, h.z));
        p.normals.push_back(n);
        p.texcoords.push_back(c * 0.5f + 0.5f);
        p.vertex_materials.push_back(axis == 2 && sign > 0 ? 1 : 0);
      }
      p.indices.insert(p.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
    }
  }
  p.materials = {Material{"wood", glm::vec4(0.5f, 0.3f, 0.1f, 1.0f), -1},
                 Material{"flame", glm::vec4(1.0f, 0.6f, 0.1f, 1.0f), 0}};
  p.images.push_back(Image{1, 1, {255, 255, 255, 255}});
  return p;
}

inline glm::mat4 gripOffset() {
  glm::mat4 m = glm::mat4_cast(glm::angleAxis(0.4f, glm::vec3(1, 0, 0)));
  m[3] = glm::vec4(0.01f, -0.08f, 0.02f, 1.0f);
  return m;
}

}  // namespace si::test
