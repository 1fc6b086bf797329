// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the view render tests share (crowd_view_render_test.cpp, gpu_views_render_test.cpp): a
// sun-like orthographic light camera, a row of characters behind the main camera (which it
// culls and the light sees), and the depth read-back of a shadow view.
#include <glad/gl.h>

#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "render/render_fixture.h"

namespace si::test {

/// An orthographic camera at `target + offset` looking at `target`, `half` units either side.
inline Camera lightCamera(const glm::dvec3& target, const glm::dvec3& offset, float half) {
  Camera c;
  c.position = target + offset;
  c.view_rotation = glm::lookAt(glm::vec3(0.0f), glm::vec3(-offset), glm::vec3(0, 1, 0));
  c.projection = glm::ortho(-half, half, -half, half, 1.0f, 200.0f);
  c.viewport_height_pixels = float(kSize);
  return c;
}

/// Four characters at z = 9, behind the main cameras of the view tests (appended to `behind`).
inline void addRowBehind(CrowdManager* crowd, std::vector<InstanceHandle>* behind) {
  for (int k = 0; k < 4; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3(k * 2.0 - 3.0, 0.0, 9.0);
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(d, &h).isOk());
    if (behind != nullptr) behind->push_back(h);
  }
}

/// The bound framebuffer's depth, kSize x kSize.
inline std::vector<float> readDepth() {
  std::vector<float> depth(size_t(kSize) * kSize, -1.0f);
  glReadPixels(0, 0, GLsizei(kSize), GLsizei(kSize), GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  return depth;
}

}  // namespace si::test
