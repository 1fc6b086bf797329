// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The embedded character's skeleton (joints, rest positions), shared by default_character.cpp
// (mesh, texture, assembly) and default_clips.cpp (the clips).

#include <algorithm>
#include <array>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/clip.h"

namespace si::detail::embedded {

inline constexpr double kPi = 3.14159265358979323846;

enum Joint : int {
  kRoot, kPelvis, kSpine, kChest, kNeck, kHead,
  kLClavicle, kLUpperArm, kLForearm, kLHand,
  kRClavicle, kRUpperArm, kRForearm, kRHand,
  kLThigh, kLShin, kLFoot, kRThigh, kRShin, kRFoot,
  kRWeapon, kLShield, kJointCount
};

struct JointDef {
  const char* name;
  int parent;
  glm::dvec3 position;  // Model space, rest pose.
};

inline const std::array<JointDef, kJointCount> kJoints = {{
    {"root", -1, {0, 0, 0}},
    {"pelvis", kRoot, {0, 0.95, 0}},
    {"spine", kPelvis, {0, 1.10, 0}},
    {"chest", kSpine, {0, 1.28, 0}},
    {"neck", kChest, {0, 1.46, 0}},
    {"head", kNeck, {0, 1.57, 0}},
    {"l_clavicle", kChest, {0.04, 1.43, 0}},
    {"l_upperarm", kLClavicle, {0.19, 1.42, 0}},
    {"l_forearm", kLUpperArm, {0.24, 1.15, 0}},
    {"l_hand", kLForearm, {0.27, 0.91, 0.02}},
    {"r_clavicle", kChest, {-0.04, 1.43, 0}},
    {"r_upperarm", kRClavicle, {-0.19, 1.42, 0}},
    {"r_forearm", kRUpperArm, {-0.24, 1.15, 0}},
    {"r_hand", kRForearm, {-0.27, 0.91, 0.02}},
    {"l_thigh", kPelvis, {0.10, 0.92, 0}},
    {"l_shin", kLThigh, {0.10, 0.50, 0.01}},
    {"l_foot", kLShin, {0.10, 0.09, 0}},
    {"r_thigh", kPelvis, {-0.10, 0.92, 0}},
    {"r_shin", kRThigh, {-0.10, 0.50, 0.01}},
    {"r_foot", kRShin, {-0.10, 0.09, 0}},
    {"r_weapon", kRHand, {-0.27, 0.84, 0.05}},
    {"l_shield", kLForearm, {0.31, 1.04, 0}},
}};

/// Joint j's rest offset from its parent (model space; rest rotations are identity).
inline glm::dvec3 restOffset(int j) {
  const int p = kJoints[size_t(j)].parent;
  return kJoints[size_t(j)].position - (p >= 0 ? kJoints[size_t(p)].position : glm::dvec3(0.0));
}

/// Hermite smoothstep of v between e0 and e1 (the mesh's weight blends, the wave's envelope).
inline double smoothstep(double e0, double e1, double v) {
  const double t = std::clamp((v - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

/// The clips in palette order: idle, walk, run, wave and, with `moving_clips`, walk_forward and
/// walk_turn_left (marked for root motion extraction).
std::vector<Clip> defaultClips(bool moving_clips);

}  // namespace si::detail::embedded
