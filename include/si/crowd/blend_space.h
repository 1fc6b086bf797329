// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Blend spaces: a steady blend of clips placed along one parameter (walk at speed 1.4, run at
/// 4, sprint at 7), each instance at its own value (CrowdManager::playBlend,
/// setBlendParameter). At any value the two clips around it blend (one at the ends), phase
/// synchronised: both advance through the same fraction of their cycle, at a period between
/// their lengths weighted as they are blended, so feet stay in step while the parameter moves.
///
/// The blend is the reference's local-space blend (each joint's local rotation slerped,
/// translation and scale lerped, composed from the root: si::evaluateLayeredPose on a full-body
/// mask): the lower clip plays as the instance's clip and the upper as its overlay on the space's
/// mask (si::buildFullBodyMask) at the blend weight, so every path (vertex-shader, compute,
/// GPU-driven, depth-only, motion vectors) draws it through the layered-animation machinery,
/// and it costs what an overlay costs: a 16-byte layer record per drawn instance, no vertex
/// cost beyond the composed rows. An instance blends or plays an overlay, not both.
///
/// Usage:
/// \code
///   si::LayerMask body;
///   si::buildFullBodyMask(character.skeleton, palette, "body", &body);
///   uint32_t body_mask = 0, locomotion = 0;
///   crowd.addLayerMask(body, &body_mask);
///   si::BlendSpace space{"locomotion", {walk, run}, {1.4f, 4.0f}, body_mask};
///   crowd.addBlendSpace(space, &locomotion);
///   crowd.playBlend(h, locomotion, 2.0f, 0.3);   // at speed 2, crossfading in over 0.3 s
///   crowd.setBlendParameter(h, 3.1f);            // each frame, from the gameplay speed
/// \endcode

#include <cstdint>
#include <string>
#include <vector>

#include "si/core/baked_palette.h"
#include "si/core/status.h"

namespace si {

/// Clips of one blend space, at most.
inline constexpr uint32_t kMaxBlendClips = 16;

/// Clips along a parameter, and the crowd layer mask their blend composes on.
struct BlendSpace {
  std::string name;
  std::vector<uint32_t> clips;   ///< Palette clips, 2 to kMaxBlendClips.
  std::vector<float> positions;  ///< One per clip: the parameter where it plays alone, increasing.
  /// The crowd's layer mask (CrowdManager::addLayerMask) the upper clip composes on: a full-body
  /// mask (si::buildFullBodyMask) blends the whole character; a partial one blends only its
  /// joints, the rest following the lower clip.
  uint32_t mask = 0;

  /// kInvalidArgument naming the rule: a name; 2 to kMaxBlendClips clips, each below the
  /// palette's clip count; one finite position per clip, strictly increasing; the mask below
  /// `mask_count`.
  Status validate(const BakedPalette& palette, uint32_t mask_count) const;
};

/// The two clips blended at one parameter value: indices into BlendSpace::clips and the weight
/// of the upper one (0 at the lower's position, 1 at the upper's).
struct BlendPair {
  uint32_t lower = 0;
  uint32_t upper = 0;
  float weight = 0.0f;
};

/// The pair at `parameter` (clamped to the first and last positions; NaN reads as the first):
/// the neighbours around it, weighted linearly between their positions. At or past the last
/// position, the last two with weight 1. `positions` must be valid (BlendSpace::validate).
BlendPair blendPair(const std::vector<float>& positions, float parameter);

/// The cycle period of a phase-synchronised blend: the two clips' durations weighted as they
/// are blended, (1 - weight) * lower + weight * upper; each clip plays at its duration over it
/// (times the instance's speed), so both pass through the same fraction of their cycle.
double blendPeriod(double lower_seconds, double upper_seconds, float weight);

}  // namespace si
