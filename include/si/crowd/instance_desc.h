// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::InstanceDesc: one instance's initial state (CrowdManager::add), and RandomCrowdDesc, a
/// seeded field of them (CrowdManager::addRandom).

#include <cstdint>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "si/core/baked_palette.h"
#include "si/core/span.h"

namespace si {

/// One instance's initial state.
struct InstanceDesc {
  glm::dvec3 position = glm::dvec3(0.0);  ///< World position (double: far from the origin).
  glm::quat rotation = glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  float scale = 1.0f;                         ///< Uniform, > 0.
  /// Tint (RGB) where the texture's alpha says so. The alpha must be 255: the record's fourth
  /// byte holds `custom_layer` instead.
  glm::u8vec4 color = glm::u8vec4(255);
  /// The instance's layer of the application's custom texture array (Renderer::
  /// setCustomTextureArray): 0 for none, k for layer k - 1 (at most kMaxCustomLayers). Where the
  /// tint mask is, that layer's texel (over the base texel by its own alpha) is what the tint
  /// multiplies.
  uint8_t custom_layer = 0;
  uint32_t variation_mask = 0xFFFFFFFFu;      ///< Bit s: sub-mesh s is worn.
  uint32_t clip = 0;                          ///< Index into the palette's clips.
  double time_seconds = 0.0;                  ///< Clip-local start time.
  float speed = 1.0f;                         ///< Playback speed, >= 0.
  /// kDefault uses the clip's loop mode; kOnce holds the last frame, kLoop wraps.
  LoopMode loop_mode = LoopMode::kDefault;
  /// Root motion (si/core/root_motion.h): update() moves and turns the instance by the baked
  /// motion of what it plays (BakedClip::root_motion; clips without it do not move it), times
  /// its scale, in its own frame. Off: the application places it (setTransform()).
  bool root_motion = false;
};

/// Options of CrowdManager::addRandom(): the technique's random armour at load time.
struct RandomCrowdDesc {
  Span<const glm::dvec3> positions;  ///< One instance per position.
  uint64_t seed = 1;
  uint32_t required_mask = 1;         ///< Sub-meshes every instance wears (e.g. the body).
  uint32_t optional_mask = 0;         ///< Sub-meshes each worn with `optional_probability`.
  float optional_probability = 0.5f;
  Span<const uint32_t> clips;         ///< Clips to pick from; empty means all.
  bool random_time = true;            ///< Random start time within the clip.
  bool random_heading = true;         ///< Random rotation about +Y.
  float min_speed = 0.9f, max_speed = 1.1f;
  bool root_motion = false;           ///< InstanceDesc::root_motion of every instance.
};

}  // namespace si
