// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A palette with morph targets for the crowd tests (overlays on targets, live poses).
#pragma once

#include <string>

#include "crowd/crowd_test_helpers.h"
#include "si/core/character.h"

namespace si::test {

// The embedded character with three targets ("t0", "t1", "t2"), each moving its first 30
// vertices up; "walk" animates target k from 0.1 k to 0.5 + 0.1 k over its duration, "wave"
// from 0.9 - 0.2 k to 0.2 (LINEAR, two keys).
struct Face {
  Character character;
  BakedPalette palette;
  uint32_t walk = 0, wave = 0;
};

inline const Face& face() {
  static const Face f = [] {
    Face out;
    Character& c = out.character;
    c = test::defaultCharacter();
    for (uint32_t k = 0; k < 3; ++k) {
      MorphTarget t;
      t.name = "t" + std::to_string(k);
      for (uint32_t v = 0; v < 30; ++v) {
        t.vertices.push_back(v);
        t.position_deltas.push_back(glm::vec3(0.0f, 0.01f * float(k + 1), 0.0f));
      }
      c.mesh.morph_targets.push_back(t);
    }
    for (Clip& clip : c.clips) {
      MorphWeightTrack w;
      w.target_count = 3;
      w.interpolation = Interpolation::kLinear;
      w.times_seconds = {0.0f, clip.duration_seconds};
      const bool wave = clip.name == "wave";
      for (int key = 0; key < 2; ++key)
        for (int k = 0; k < 3; ++k)
          w.values.push_back(wave ? (key == 0 ? 0.9f - 0.2f * float(k) : 0.2f)
                                  : 0.1f * float(k) + 0.5f * float(key));
      clip.morph_tracks = {w};
    }
    out.palette = test::bakeAt30Hz(c);
    out.walk = uint32_t(out.palette.findClip("walk"));
    out.wave = uint32_t(out.palette.findClip("wave"));
    return out;
  }();
  return f;
}

}  // namespace si::test
