// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The scenes several render tests share, and the CPU selection they compare the GPU's with.
// Included at the end of render_fixture.h, whose fixture draws some of them.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <vector>

#include "render/render_fixture.h"

namespace si::test {

inline Camera closeCamera() {
  return Camera::lookAt({0.0, 1.2, 3.2}, {0.0, 1.0, 0.0}, glm::vec3(0, 1, 0), 0.75f, 1.0f, 0.1f,
                        200.0f);
}

// Every LOD, every variation and several tints: 3 rows at LOD distances, 8 masks each.
inline void populateLodCrowd(CrowdManager* crowd) {
  const uint32_t clips = uint32_t(palette().clips.size());
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k < 8; ++k) {
      InstanceDesc d;
      const double z = row == 0 ? -4.0 : row == 1 ? -40.0 : -110.0;
      const double spacing = row == 0 ? 1.2 : row == 1 ? 6.0 : 16.0;
      d.position = glm::dvec3((k - 3.5) * spacing, 0.0, z);
      d.variation_mask = 1u | (uint32_t(k) << 1);
      d.clip = uint32_t(k) % clips;
      d.time_seconds = 0.1 * k;
      d.speed = 0.0f;
      d.color =
          glm::u8vec4(uint8_t(40 + 30 * k), uint8_t(200 - 20 * k), uint8_t(60 + 60 * row), 255);
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
    }
}

// Occlusion culling's scene: a dense wall of 3 staggered rows of 40 characters, shoulder to
// shoulder 2 units in front of wallCamera(), and a crowd of 600 behind it (seeded).
inline void populateWallCrowd(CrowdManager* crowd) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k < 40; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3(-6.0 + 0.3 * k + 0.15 * row, 0.0, -2.0 - 0.4 * row);
      d.clip = uint32_t(k % 2);
      d.time_seconds = u(rng);
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
    }
  for (int k = 0; k < 600; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3(-8.0 + 16.0 * u(rng), 0.0, -8.0 - 30.0 * u(rng));
    d.clip = uint32_t(k % 3);
    d.time_seconds = u(rng);
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(d, &h).isOk());
  }
}
// At eye height in front of the wall, looking along -z.
inline Camera wallCamera() {
  return Camera::lookAt({0.0, 1.0, 2.0}, {0.0, 1.0, -40.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                        500.0f);
}

// One more character, close to the camera, crossfading from clip 0 to run over 1 s from the
// crowd clock's current time (the tests then advance it 0.3 s).
inline void addFadingCharacter(CrowdManager* crowd,
                               PaletteFormat format = PaletteFormat::kMatrix3x4F32) {
  InstanceHandle fading;
  InstanceDesc d;
  d.position = glm::dvec3(0.5, 0.0, -2.0);
  ASSERT_TRUE(crowd->add(d, &fading).isOk());
  ASSERT_TRUE(crowd->crossfade(fading, uint32_t(palette(format).findClip("run")), 1.0).isOk());
}

// Sixteen characters of impostorCharacter() in two rows of 8, `spacing` apart, the first row at
// z = -`z` (in front of lodCamera()) and the second `row_step` further, every one at the
// impostor level (each mesh level's line 2 radii after the last), updated 0.2 s.
inline void impostorRowsCrowd(double spacing, double z, double row_step, CrowdManager* crowd) {
  const uint32_t levels = uint32_t(impostorCharacter().mesh.maxLodCount());
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = 4;
  cd.lod_count = levels;
  cd.character_radius = 1.0f;
  for (uint32_t l = 1; l < levels; ++l) cd.lod_distances_radii.push_back(2.0f * float(l));
  cd.max_distance_radii = -1.0f;
  cd.impostor_lod = levels - 1;
  ASSERT_TRUE(crowd->init(cd).isOk());
  for (int k = 0; k < 16; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3((k % 8 - 3.5) * spacing, 0.0, -z - row_step * (k / 8));
    d.rotation = glm::angleAxis(0.7f * float(k), glm::vec3(0, 1, 0));
    d.clip = uint32_t(k) % uint32_t(palette().clips.size());
    d.color = glm::u8vec4(uint8_t(40 + 12 * k), 200, 90, 255);
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(d, &h).isOk());
  }
  ASSERT_TRUE(crowd->update(0.2, lodCamera()).isOk());
  ASSERT_EQ(crowd->view().stats().per_lod[levels - 1], 16u);
}

// The CPU's selection of the last update(): (dense index as CrowdExport::state orders it, LOD) per
// visible instance.
inline std::vector<glm::uvec2> cpuSelection(const CrowdManager& crowd) {
  std::vector<GpuInstanceState> state;
  std::vector<InstanceHandle> dense;
  si::CrowdExport(crowd).state(&state, &dense);
  std::map<uint32_t, uint32_t> dense_of;  // handle id -> dense index
  for (uint32_t i = 0; i < dense.size(); ++i) dense_of[dense[i].id] = i;
  std::vector<glm::uvec2> out;
  for (InstanceHandle h : crowd.view().visibleHandles()) {
    uint32_t lod = 0;
    EXPECT_TRUE(crowd.view().lodOf(h, &lod).isOk());
    out.push_back(glm::uvec2(dense_of[h.id], lod));
  }
  return out;
}

inline Camera lodCamera() {
  return Camera::lookAt({0.0, 3.0, 6.0}, {0.0, 0.0, -40.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                        500.0f);
}

}  // namespace si::test
