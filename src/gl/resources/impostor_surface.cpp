// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Whether an impostor atlas's surface layer holds one value, read back from the atlas.
#include "gl/resources/impostor_surface.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "si/gl/gl_context.h"

namespace si::detail {

Status measureUniformSurface(GLuint atlas, uint32_t width, uint32_t height, uint32_t* uniform) {
  *uniform = 0;
  constexpr GLint kSurfaceLayer = 2;
  const uint32_t band_rows =
      std::max<uint32_t>(1, uint32_t((16u << 20) / (uint64_t(std::max(width, 1u)) * 4)));
  std::vector<uint32_t> band;
  uint32_t value = 0;  // The first drawn texel's (never 0: its code is at least 1).
  for (uint32_t y0 = 0; y0 < height; y0 += band_rows) {
    const uint32_t n = std::min(band_rows, height - y0);
    band.resize(size_t(width) * n);
    glGetTextureSubImage(atlas, 0, 0, GLint(y0), kSurfaceLayer, GLsizei(width), GLsizei(n), 1,
                         GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(band.size() * 4), band.data());
    const Status s = checkGlErrors("buildImpostor: reading the atlas's surface layer back");
    if (!s.isOk()) return s;
    for (const uint32_t texel : band) {
      uint8_t bytes[4];
      std::memcpy(bytes, &texel, 4);
      if (bytes[3] == 0) continue;  // Nothing drawn there.
      const uint32_t packed = uint32_t(bytes[0]) | uint32_t(bytes[1]) << 8 |
                              uint32_t(bytes[2]) << 16 | uint32_t(bytes[3]) << 24;
      if (value == 0) value = packed;
      if (packed != value) return Status::ok();  // The layer varies.
    }
  }
  *uniform = value;
  return Status::ok();
}

}  // namespace si::detail
