// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A palette of the embedded character shared by the crowd tests (fixed 30 Hz, no report).

#include <cstdlib>

#include "core/test_helpers.h"
#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/crowd/crowd_manager.h"

namespace si::test {

inline const Character& defaultCharacter() {
  static const Character c = [] {
    Character out;
    if (!makeDefaultCharacter({}, &out).isOk()) std::abort();
    return out;
  }();
  return c;
}

/// `character` baked at a fixed 30 Hz without a report (a failure aborts: every crowd test
/// needs it).
inline BakedPalette bakeAt30Hz(const Character& character) {
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = 30.0f;
  BakedPalette out;
  if (!bakePalette(character, d, &out, nullptr).isOk()) std::abort();
  return out;
}

inline const BakedPalette& defaultPalette() {
  static const BakedPalette p = bakeAt30Hz(defaultCharacter());
  return p;
}

/// The embedded character with its travelling clips (DefaultCharacterDesc::moving_clips), and
/// its palette (fixed 30 Hz; the travelling clips baked in place with their root motion).
inline const Character& movingCharacter() {
  static const Character c = travellingCharacter();
  return c;
}

inline const BakedPalette& movingPalette() {
  static const BakedPalette p = bakeAt30Hz(movingCharacter());
  return p;
}

inline CrowdDesc defaultCrowdDesc() {
  CrowdDesc d;
  d.palette = &defaultPalette();
  d.sub_mesh_count = uint32_t(defaultCharacter().mesh.sub_meshes.size());
  d.lod_count = uint32_t(defaultCharacter().mesh.maxLodCount());
  return d;
}

/// A camera at `eye` looking at `target`, 60 degrees vertical, 16:9, near 0.1, far 5000.
inline Camera testCamera(glm::dvec3 eye, glm::dvec3 target) {
  return Camera::lookAt(eye, target, glm::vec3(0, 1, 0), 1.0471976f, 16.0f / 9.0f, 0.1f, 5000.0f);
}

}  // namespace si::test
