// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The palette on the GPU: one RGBA32F (or RGBA16F) texture read with texelFetch, and the
// include's si_palette_info uniform value.

#include <glad/gl.h>

#include <glm/glm.hpp>

#include "gl/programs/program_set.h"
#include "si/core/baked_palette.h"
#include "si/gl/gl_context.h"

namespace si::detail {

class PaletteTexture {
 public:
  /// Uploads `palette` (borrowed: it must outlive the upload's use). kInvalidArgument for a
  /// palette that fails BakedPalette::validate(); kLimitExceeded past GL_MAX_TEXTURE_SIZE.
  Status upload(const BakedPalette& palette, const GlInfo& info);
  void release();

  GLuint texture() const { return texture_; }
  const glm::uvec4& shaderInfo() const { return shader_info_; }
  const BakedPalette* palette() const { return palette_; }
  bool ready() const { return texture_ != kNoObject; }

 private:
  GLuint texture_ = kNoObject;
  glm::uvec4 shader_info_{0};
  const BakedPalette* palette_ = nullptr;
};

}  // namespace si::detail
