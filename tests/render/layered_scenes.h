// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The layered animation tests' scene (si::gl's layered_render_test.cpp, si::vk's
// vk_layers_test.cpp): walkers of the embedded character, two thirds waving an arm (an overlay
// on the mask rooted at a joint), and the close camera that sees them; the 2D blend space the
// blend tests play (blend_2d_render_test.cpp, vk_layers_test.cpp).
#include <gtest/gtest.h>

#include <vector>

#include "render/render_fixture.h"
#include "si/core/layer_mask.h"

namespace si::test {

// The close camera of the walkers, `f` tenths of a unit to the right.
inline Camera wavingView(int f = 0) {
  return Camera::lookAt({0.1 * f, 1.6, 2.5}, {0.0, 1.0, -4.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                        100.0f);
}

// 12 instances walking into `crowd` (initialized for the embedded character), shifted by
// `offset`; two thirds play the wave on the mask rooted at `branch`, at once or fading in over
// 1 s. Their handles are appended to `handles`. Not updated.
inline void populateWavingCrowd(CrowdManager* crowd, std::vector<InstanceHandle>* handles,
                                const char* branch = "r_clavicle",
                                const glm::dvec3& offset = glm::dvec3(0.0)) {
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(character().skeleton, palette(), branch, {branch}, &arm).isOk());
  uint32_t mask = 0;
  ASSERT_TRUE(crowd->addLayerMask(arm, &mask).isOk());
  const uint32_t walk = uint32_t(palette().findClip("walk"));
  const uint32_t wave = uint32_t(palette().findClip("wave"));
  for (int k = 0; k < 12; ++k) {
    InstanceDesc d;
    d.position = offset + glm::dvec3((k % 4 - 1.5) * 1.2, 0.0, -2.5 - 1.5 * (k / 4));
    d.rotation = glm::angleAxis(0.6f * float(k % 3 - 1), glm::vec3(0, 1, 0));
    d.clip = walk;
    d.time_seconds = 0.11 * k;
    d.color = glm::u8vec4(uint8_t(60 + 15 * k), uint8_t(220 - 12 * k), 120, 255);
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(d, &h).isOk());
    handles->push_back(h);
    // Two thirds wave: at once, or fading in over 1 s (half-way at an update of 0.5 s).
    if (k % 3 != 2) {
      ASSERT_TRUE(crowd->playOverlay(h, wave, mask, 1.0f, k % 3 == 0 ? 0.0 : 1.0, 0.13 * k).isOk());
    }
  }
}

// The embedded character's idle, walk, run and wave clips on a 2x2 grid (x and y from 0 to 1),
// composed on the crowd's layer mask `mask`.
inline BlendSpace idleWalkRunWaveGrid(uint32_t mask) {
  const auto clip = [](const char* name) { return uint32_t(palette().findClip(name)); };
  BlendSpace grid;
  grid.name = "grid";
  grid.clips = {clip("idle"), clip("walk"), clip("run"), clip("wave")};
  grid.positions = {0.0f, 1.0f};
  grid.positions_y = {0.0f, 1.0f};
  grid.mask = mask;
  return grid;
}

}  // namespace si::test
