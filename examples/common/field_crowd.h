// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The examples' field: a square grid of characters, each its own clip, time and tint.

#include <cmath>
#include <cstdint>

#include <glm/gtc/quaternion.hpp>

#include "si/core/baked_palette.h"
#include "si/crowd/crowd_manager.h"

namespace si::examples {

/// Adds `n` characters of `palette` to `crowd` on a square grid 1.6 units apart, centred on the
/// origin, each turned, with its own clip, time and tint; `*half_side` gets half the grid's
/// side plus a margin of 4 units (where cameras and lights are placed).
inline Status populateField(uint32_t n, const BakedPalette& palette, CrowdManager* crowd,
                            float* half_side) {
  const uint32_t side = uint32_t(std::ceil(std::sqrt(double(n))));
  *half_side = 0.8f * float(side) + 4.0f;
  for (uint32_t i = 0; i < n; ++i) {
    InstanceDesc d;
    d.position = glm::dvec3((double(i % side) - 0.5 * side) * 1.6, 0.0,
                            (double(i / side) - 0.5 * side) * 1.6);
    d.rotation = glm::angleAxis(0.37f * float(i), glm::vec3(0, 1, 0));
    d.clip = i % uint32_t(palette.clips.size());
    d.time_seconds = 0.173 * i;
    d.color = glm::u8vec4(uint8_t(120 + (i * 37) % 120), uint8_t(120 + (i * 53) % 120),
                          uint8_t(120 + (i * 71) % 120), 255);
    InstanceHandle h;
    const Status s = crowd->add(d, &h);
    if (!s.isOk()) return s;
  }
  return Status::ok();
}

}  // namespace si::examples
