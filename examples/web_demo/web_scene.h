// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The browser page's scene, shared by the page (web_main.cpp) and its native twin
// (web_reference.cpp), so that the browser test compares the same crowd from the same camera at
// the same time: the embedded character on a grid 1.6 m apart, random clips, times, headings
// and parts from one seed, seen by an orbit camera about the field's centre.
#include <cstdint>

#include "si/core/character.h"
#include "si/crowd/camera.h"
#include "si/crowd/crowd_manager.h"

namespace si::web {

inline constexpr uint32_t kDefaultInstances = 2500;
inline constexpr uint64_t kSeed = 7;
/// The test mode's fixed step (the page's ?test=FRAMES): frame k (from 0) plays at k / 30 s.
inline constexpr double kTestStepSeconds = 1.0 / 30.0;

struct Orbit {
  double yaw = 0.6, pitch = 0.35, distance = 30.0;
};

/// Inits `crowd` for `character` and `palette` (one update thread) with `instances` characters.
Status buildCrowd(const Character& character, const BakedPalette& palette, uint32_t instances,
                  CrowdManager* crowd);

/// The orbit camera about the centre of a field of `instances`.
Camera orbitCamera(const Orbit& orbit, uint32_t instances, float aspect);

}  // namespace si::web
