// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// An RGBA8 texture array's layer read back band by band (the impostor atlas's coverage and
// surface measurements, impostor_coverage.h and impostor_surface.h): at most 16 MiB held at a
// time, whatever the atlas's size.

#include <glad/gl.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "si/core/status.h"
#include "si/gl/gl_context.h"

namespace si::detail {

/// Reads layer `layer` of mip level `level` (`width` x `height` texels, RGBA8) of `texture`
/// back in bands of whole rows from the bottom, at most 16 MiB each, and calls
/// `band(y0, rows, texels)` for each (`rows` rows of `width` texels from row `y0`, 4 bytes a
/// texel) until it returns false. A GL error stops it with kBackend naming `what`. Needs the
/// default pixel-pack state (GlStateGuard's readback footprint).
template <typename Band>
Status readLayerBands(GLuint texture, GLint level, GLint layer, uint32_t width, uint32_t height,
                      const char* what, Band&& band) {
  const uint32_t band_rows =
      std::max<uint32_t>(1, uint32_t((16u << 20) / (uint64_t(std::max(width, 1u)) * 4)));
  std::vector<uint8_t> texels;
  for (uint32_t y0 = 0; y0 < height; y0 += band_rows) {
    const uint32_t rows = std::min(band_rows, height - y0);
    texels.resize(size_t(width) * rows * 4);
    glGetTextureSubImage(texture, level, 0, GLint(y0), layer, GLsizei(width), GLsizei(rows), 1,
                         GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(texels.size()), texels.data());
    const Status s = checkGlErrors(what);
    if (!s.isOk()) return s;
    if (!band(y0, rows, texels.data())) break;
  }
  return Status::ok();
}

}  // namespace si::detail
