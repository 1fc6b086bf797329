// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A production-style stress character, generated (no downloaded data): a dense mesh in many
// parts on a 36-joint humanoid, and one long motion-capture-like clip with dense LINEAR keys
// on the translation, rotation and scale of every joint and fast limb rotations.
#include <cstdint>

#include "si/core/character.h"

namespace si::test {

struct StressDesc {
  float duration_seconds = 32.0f;  ///< The clip's length.
  float key_rate_hz = 37.5f;       ///< Keys per second on every track (not a multiple of 30).
  uint32_t rings = 24;             ///< Vertex rings along each limb's tube.
  uint32_t around = 40;            ///< Vertices around each ring.
  /// Scales every joint's rotation amplitudes; 1 gives the peaks documented on
  /// makeStressCharacter().
  float motion_scale = 1.0f;
};

/// The stress character (deterministic: the same desc gives bit-identical data).
/// - Skeleton: 36 joints (hips, spine, neck, head; two arms of clavicle, upper arm, forearm,
///   hand and two two-joint fingers; two legs of thigh, shin, foot and toe; a six-joint cape),
///   height 1.76 units.
/// - Mesh: one tube of `rings` x `around` vertices per bone (35 tubes; 33,600 vertices by
///   default) in 30 sub-meshes; every vertex weighted to up to 4 joints (its bone's, the next
///   and the previous near the ends), and every ninth vertex with a weight of 1e-6 on the root
///   (quantized to 0 by the vertex format).
/// - Clip "mocap" (kOnce): keys at k / key_rate_hz on every track of every joint, LINEAR.
///   Each rotation is the product of rotations about X, Y and Z by angles
///   a(t) = sum of three sines + a per-key jitter of at most 0.003 rad;
///   stressMaxAngularSpeed() bounds |da/dt| over all joints: 14.1 rad/s (808 degrees per
///   second) on the forearms and shins, before jitter.
///   Translations: the rest offset plus a bob and sway of the hips (0.05 units) and a jitter of
///   at most 0.002 units on every joint. Scales: uniform, 1 +- 0.03 on the spine and cape, 1
///   elsewhere (still keyed).
Character makeStressCharacter(const StressDesc& desc = {});

/// The bound on |da/dt| over every angle of every joint at motion_scale 1, radians per second.
double stressMaxAngularSpeed();

}  // namespace si::test
