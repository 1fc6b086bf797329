// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// One character's impostor atlas on the GPU (Renderer::buildImpostor fills it): the texture
// array of three layers, the clip table the impostor vertex shader finds frames in, and the
// numbers its uniforms carry (shaders/impostor.vert.glsl).

#include <glad/gl.h>

#include <cstdint>

#include <glm/glm.hpp>

#include "crowd/impostor_plan.h"
#include "gl/programs/program_set.h"
#include "si/crowd/camera.h"

namespace si::detail {

struct ImpostorAtlas : ImpostorGrid {
  /// Base colour and coverage; normal and tint mask; metallic, roughness, occlusion and the
  /// material's code (impostor_capture_material.glsl).
  static constexpr uint32_t kLayers = 3;
  static constexpr uint32_t kSurfaceLayer = 2;  ///< Metallic, roughness, occlusion, code.

  GLuint texture = kNoObject;  ///< GL_TEXTURE_2D_ARRAY, RGBA8, kLayers layers, mipmapped.
  /// Storage: per clip (first texel, frames, first cell frame, frames), then per cell and mip
  /// level its covered rectangle (impostor_coverage.h), cell c's level l at word
  /// clip_count * 4 + c * levels + l.
  GLuint clips = kNoObject;
  /// The surface layer's one value where the capture drew (R | G << 8 | B << 16 | A << 24:
  /// metallic, roughness, occlusion, the material's code; measureUniformSurface), handed to
  /// the impostor fragment stage instead of read; 0 where the layer varies.
  uint32_t uniform_surface = 0;

  bool ready() const { return texture != kNoObject; }
  /// Binds the atlas (texture unit 3, storage binding 9) and sets `program`'s impostor
  /// uniforms for `camera` and the current viewport (which the quads' mip level estimate
  /// projects to). A program that reads quads computed before (the GPU-driven impostor draw,
  /// `quads_computed`) takes only the texture, the grid and the camera's back direction.
  void bind(const Program& program, const Camera& camera, bool quads_computed = false) const;
  /// Deletes the texture and the clip table (context current). Idempotent.
  void release();
};

}  // namespace si::detail
