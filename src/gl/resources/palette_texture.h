// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The palette on the GPU: one RGBA32F (or RGBA16F) texture read with texelFetch, and the
// include's si_palette_info value in a 16-byte uniform buffer (block SiPaletteInfo).

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
  /// The uniform buffer holding shaderInfo(), for block SiPaletteInfo.
  GLuint infoBuffer() const { return info_buffer_; }
  /// Binds the texture at unit 0 and the info block at uniform binding 4 (the include's
  /// SI_PALETTE_BINDING and SI_PALETTE_INFO_BINDING defaults, which the library's programs use).
  void bind() const;
  const BakedPalette* palette() const { return palette_; }
  bool ready() const { return texture_ != kNoObject; }
  uint64_t gpuBytes() const;  ///< The texture's and the info block's.

 private:
  GLuint texture_ = kNoObject, info_buffer_ = kNoObject;
  glm::uvec4 shader_info_{0};
  const BakedPalette* palette_ = nullptr;
};

}  // namespace si::detail
