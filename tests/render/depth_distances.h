// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Depth under every si::DepthConvention, for the tests that compare one convention's depth
// buffer with another's (OpenGL's clip control, the Vulkan back-end): a camera's projection in
// another convention, window depth back to distances along the view axis, and how many covered
// pixels of two such images are apart.
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "si/crowd/camera.h"

namespace si::test {

// `standard` (a lookAt camera) with `convention`'s projection: OpenGL's -1 to 1 as it is,
// zero-to-one (glm's ZO perspective, the same near and far), or reverse-Z with an infinite far
// plane.
inline Camera withConvention(const Camera& standard, DepthConvention convention, float fov,
                             float near_plane, float far_plane) {
  Camera c = standard;
  c.depth = convention;
  if (convention == DepthConvention::kZeroToOne)
    c.projection = glm::perspectiveRH_ZO(fov, 1.0f, near_plane, far_plane);
  if (convention == DepthConvention::kReversedZeroToOne) {
    const Camera reversed =
        Camera::lookAtReverseZ({0, 0, 0}, {0, 0, -1}, glm::vec3(0, 1, 0), fov, 1.0f, near_plane);
    c.projection = reversed.projection;
  }
  return c;
}

// Distance along the view axis of window depth `d` under `camera` (depth range 0-1; clip z =
// A z + B, w = -z), or -1 for the cleared background.
inline std::vector<float> viewDistances(const std::vector<float>& depth, const Camera& camera) {
  const float a = camera.projection[2][2], b = camera.projection[3][2];
  const bool reversed = camera.depth == DepthConvention::kReversedZeroToOne;
  std::vector<float> out(depth.size(), -1.0f);
  for (size_t i = 0; i < depth.size(); ++i) {
    const float d = depth[i];
    if (reversed ? d <= 0.0f : d >= 1.0f) continue;
    const float ndc = camera.depth == DepthConvention::kNegativeOneToOne ? 2.0f * d - 1.0f : d;
    out[i] = b / (ndc + a);  // -z
  }
  return out;
}

// Pixels covered in either of two distance images (viewDistances), and how many of them are
// apart: more than a thousandth of the distance (24-bit standard depth at 110 units is the
// coarser of two conventions), or background in one of them (a silhouette).
struct DistanceDiff {
  size_t covered = 0;
  size_t apart = 0;
};
inline DistanceDiff compareDistances(const std::vector<float>& a, const std::vector<float>& b) {
  DistanceDiff d;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (a[i] < 0.0f && b[i] < 0.0f) continue;
    ++d.covered;
    d.apart += std::abs(a[i] - b[i]) > 1e-3f * std::max(1.0f, b[i]);
  }
  return d;
}

}  // namespace si::test
