// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// One texel of a baked palette as the shader's texelFetch returns it: four floats, half floats
// widened. Shared by the CPU emulation (baked_palette.cpp) and the validation.
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#include "si/core/baked_palette.h"

namespace si::detail {

/// Linear texel `index` of `p` (which must lie inside its texel bytes).
inline glm::vec4 paletteTexel(const BakedPalette& p, uint32_t index) {
  glm::vec4 v;
  if (p.format == PaletteFormat::kMatrix3x4F16) {
    uint16_t h[4];
    std::memcpy(h, p.texel_bytes.data() + size_t(index) * 8, 8);
    for (int c = 0; c < 4; ++c) v[c] = halfToFloat(h[c]);
  } else {
    std::memcpy(&v[0], p.texel_bytes.data() + size_t(index) * 16, 16);
  }
  return v;
}

}  // namespace si::detail
