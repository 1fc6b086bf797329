// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// deferred_host's G-buffer: three colour targets and a depth buffer of the host's, the
// si::MaterialDesc that writes the crowd's surface into them (meshes and impostors alike), and
// the host's own ground written the same way.
//   target 0 (RGBA16F): albedo (siSurfaceAlbedo: base colour, tint), occlusion;
//   target 1 (RGBA16F): world normal, kind (0 nothing, 0.25 ground, 0.5 impostor, 1 mesh);
//   target 2 (RGBA8): metallic, roughness.

#include <cstdint>

#include "si/crowd/camera.h"
#include "si/gl/material.h"

namespace deferred {

class GBuffer {
 public:
  /// The material the crowd draws with (Renderer::addMaterial).
  static si::MaterialDesc material();

  /// Creates the targets and the ground's program (the context current).
  si::Status init(uint32_t width, uint32_t height);
  void release();
  /// Binds the G-buffer with its viewport and clears it (nothing: kind 0, depth 1).
  void bindAndClear() const;
  /// Draws the ground (y = 0, a square of `half_side` round the origin) seen by `camera`.
  void drawGround(const si::Camera& camera, float half_side) const;
  uint32_t texture(int target) const { return colour_[target]; }
  uint32_t depthTexture() const { return depth_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

 private:
  uint32_t width_ = 0, height_ = 0;
  uint32_t framebuffer_ = 0, colour_[3] = {}, depth_ = 0;
  uint32_t ground_program_ = 0, vao_ = 0;
};

}  // namespace deferred
