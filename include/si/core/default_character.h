// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The embedded default character: a procedural humanoid that needs no files, so the demo and
/// the tests run anywhere.
///
/// It has 22 joints (a ground-level `root` that no vertex is weighted to, pelvis, spine, chest,
/// neck, head, clavicles, arms, hands, legs, feet, and two attachment joints). The body is about
/// 1.8 units tall (Y up, facing +Z); with the upright spear the bind-pose bounds, and so
/// Character::height(), reach about 2.05. Its mesh is built from capsules with smooth 2-3 joint
/// weights where the pieces meet, and has four sub-meshes: `body` (always worn), `helmet`,
/// `shield` and `spear`, each with three LODs (body 4104, 1140 and 228 triangles). Clips:
/// `idle`, `walk`, `run` (looping; `run` uses CUBICSPLINE keys) and `wave` (plays once; the
/// right hand's rotation uses STEP keys). One 64x64 RGBA8 texture: its alpha is the tint mask
/// (1 on the clothes, 0 on skin, metal and wood).

#include "si/core/character.h"

namespace si {

/// Options of the procedural character.
struct DefaultCharacterDesc {
  /// Number of LOD levels to build, 1 to 3 (0 means the default, 3).
  uint32_t lod_count = 0;
  /// Adds two clips that travel, after the four above: `walk_forward` (the walk, its root joint
  /// moving 1.3 units per second along +Z) and `walk_turn_left` (the walk at 1 unit per second
  /// on a circle, turning left pi/4 radians per second). Both loop and are marked for root
  /// motion extraction (Clip::root_motion; clear the flag to bake the travel into the poses).
  bool moving_clips = false;
};

/// Returns the desc with zeros replaced by their documented defaults.
DefaultCharacterDesc resolveDefaults(const DefaultCharacterDesc& desc);

/// Builds the embedded character. Deterministic: the same desc gives bit-identical data.
/// Fails with kOutOfRange when lod_count is above 3; `out` is then untouched.
Status makeDefaultCharacter(const DefaultCharacterDesc& desc, Character* out);

}  // namespace si
