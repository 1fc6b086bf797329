// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A crowd of 40,000 positions cheap to draw: 12 in view of closeCamera() around the origin, the
// rest behind it. Its whole state (40,000 x 144 bytes) is more than one staging chunk.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace si::test {

inline std::vector<glm::dvec3> twelveInViewOfForty() {
  std::vector<glm::dvec3> positions;
  for (int i = 0; i < 12; ++i)
    positions.push_back({(i % 4 - 1.5) * 0.8, 0.0, -1.0 - (i / 4) * 1.5});
  for (uint32_t i = 0; i < 39988; ++i) positions.push_back({double(i % 200), 0.0, 50.0 + i / 200});
  return positions;
}

}  // namespace si::test
