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

#include <glm/vec2.hpp>

#include "si/core/baked_palette.h"
#include "si/core/status.h"

namespace si {

/// Clips of one blend space, at most.
inline constexpr uint32_t kMaxBlendClips = 16;

/// Where an instance plays in a blend space (CrowdManager::playBlend, setBlendParameter): a
/// number (x alone: a 1D space's parameter; setBlendParameter keeps a 2D blend's y) or a
/// glm::vec2 (x, y on a 2D space's grid). Converts implicitly from either, so a call reads
/// `crowd.playBlend(h, space, 2.0f, 0.3)` or `crowd.playBlend(h, space, glm::vec2(1, 3), 0.3)`.
struct BlendParameter {
  BlendParameter(float x) : value(x, 0.0f), has_y(false) {}  // NOLINT: a parameter reads so.
  BlendParameter(glm::vec2 xy) : value(xy), has_y(true) {}   // NOLINT: as above.
  glm::vec2 value;
  bool has_y;  ///< false: made from x alone.
};

/// Clips along a parameter (1D), or on a grid of two (2D: sideways and forward speed, a strafe
/// blend), and the crowd layer mask their blend composes on.
struct BlendSpace {
  std::string name;
  /// Palette clips, 2 to kMaxBlendClips. 2D: one per grid point, x fastest (the clip at
  /// (positions[i], positions_y[j]) is clips[j * positions.size() + i]).
  std::vector<uint32_t> clips;
  /// 1D: one per clip, the parameter where it plays alone, increasing. 2D: the grid's x lines,
  /// increasing.
  std::vector<float> positions;
  /// The crowd's layer mask (CrowdManager::addLayerMask) the upper clip composes on: a full-body
  /// mask (si::buildFullBodyMask) blends the whole character; a partial one blends only its
  /// joints, the rest following the lower clip.
  uint32_t mask = 0;
  /// Empty: a 1D space. Else the grid's y lines (at least 2, increasing): a 2D space, whose
  /// blend mixes up to four clips (the grid cell's corners, bilinear weights).
  std::vector<float> positions_y = {};

  /// Whether it is a 2D space.
  bool is2D() const { return !positions_y.empty(); }

  /// kInvalidArgument naming the rule: a name; 2 to kMaxBlendClips clips, each below the
  /// palette's clip count; one finite position per clip (2D: at least 2 finite x and y lines,
  /// one clip per grid point), strictly increasing; the mask below `mask_count`.
  Status validate(const BakedPalette& palette, uint32_t mask_count) const;
};

/// Clips one blend draws at most: a 2D space's cell corners.
inline constexpr uint32_t kMaxBlendLayers = 4;

/// The clips a blend draws at one point, in the order they compose: the first plays as the
/// instance's clip, each next one composed on what those before it gave (a layer of
/// si::emulateLayeredChain). 1D: the two around the parameter; 2D: the cell's corners
/// (x0, y0), (x1, y0), (x0, y1), (x1, y1), some at weight 0 on a grid line.
struct BlendPoint {
  uint32_t count = 0;                 ///< 2 (1D) or 4 (2D).
  uint32_t clips[kMaxBlendLayers]{};  ///< Indices into BlendSpace::clips.
  float shares[kMaxBlendLayers]{};    ///< Each clip's share of the blend, summing to 1.
  /// Clip k's weight over the blend of clips 0..k-1 (shares[k] / (shares[0] + ... + shares[k]);
  /// 0 where that sum is 0): the layer weight that composes to the shares. chain[0] is 1.
  float chain[kMaxBlendLayers]{};
};

/// The blend at (`x`, `y`) (`y` unused by a 1D space), each clamped to its first and last
/// positions (NaN reads as the first). `space` must be valid (BlendSpace::validate).
BlendPoint blendPoint(const BlendSpace& space, float x, float y = 0.0f);

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
/// (times the instance's speed), so both pass through the same fraction of their cycle. (A 2D
/// blend's period is its clips' durations weighted by their shares.)
double blendPeriod(double lower_seconds, double upper_seconds, float weight);

}  // namespace si
