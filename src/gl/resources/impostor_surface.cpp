// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Whether an impostor atlas's surface layer holds one value, read back from its capture.
#include "gl/resources/impostor_surface.h"

#include <cstring>

#include "gl/resources/atlas_bands.h"
#include "gl/resources/impostor_atlas.h"

namespace si::detail {

Status measureUniformSurface(GLuint capture, uint32_t width, uint32_t height, uint32_t* uniform) {
  *uniform = 0;
  uint8_t first[4] = {0, 0, 0, 0};  // The first drawn texel's (its code, alpha, at least 1).
  bool varies = false;
  const Status s = readLayerBands(capture, 0, GLint(ImpostorAtlas::kSurfaceLayer), width, height,
                                  "buildImpostor: reading the capture's surface layer back",
                                  [&](uint32_t, uint32_t rows, const uint8_t* texels) {
                                    for (const uint8_t* t = texels;
                                         t < texels + size_t(width) * rows * 4; t += 4) {
                                      if (t[3] == 0) continue;  // Nothing drawn there.
                                      if (first[3] == 0) std::memcpy(first, t, 4);
                                      if (std::memcmp(t, first, 4) != 0) {
                                        varies = true;
                                        return false;  // The rest need not be read.
                                      }
                                    }
                                    return true;
                                  });
  if (!s.isOk() || varies) return s;
  *uniform = uint32_t(first[0]) | uint32_t(first[1]) << 8 | uint32_t(first[2]) << 16 |
             uint32_t(first[3]) << 24;
  return Status::ok();
}

}  // namespace si::detail
