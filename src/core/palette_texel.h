// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// One texel of a baked palette as the shader's texelFetch returns it (four floats, half floats
// widened), and as the baker and the crowd's live poses store it. Shared by the CPU emulation
// (baked_palette.cpp), the validation, the bake's texels and the live poses.
#include <cstdint>
#include <cstring>
#include <limits>

#include <glm/glm.hpp>

#include "si/core/baked_palette.h"

namespace si::detail {

/// The largest magnitude `format`'s texels store as a finite number (65504 in half floats).
inline float formatRange(PaletteFormat format) {
  return format == PaletteFormat::kMatrix3x4F16 ? 65504.0f : std::numeric_limits<float>::max();
}

/// Texel `index` of `bytes`, texels of `format` (RGBA32F, or RGBA16F for kMatrix3x4F16), as the
/// shader's texelFetch returns it.
inline glm::vec4 formatTexel(PaletteFormat format, const uint8_t* bytes, size_t index) {
  glm::vec4 v;
  if (format == PaletteFormat::kMatrix3x4F16) {
    uint16_t h[4];
    std::memcpy(h, bytes + index * 8, 8);
    for (int c = 0; c < 4; ++c) v[c] = halfToFloat(h[c]);
  } else {
    std::memcpy(&v[0], bytes + index * 16, 16);
  }
  return v;
}

/// Stores `v` as texel `index` of `bytes` in `format` (half floats rounded to nearest even).
inline void storeFormatTexel(PaletteFormat format, uint8_t* bytes, size_t index,
                             const glm::vec4& v) {
  if (format == PaletteFormat::kMatrix3x4F16) {
    uint16_t h[4];
    for (int c = 0; c < 4; ++c) h[c] = floatToHalf(v[c]);
    std::memcpy(bytes + index * 8, h, 8);
  } else {
    std::memcpy(bytes + index * 16, &v[0], 16);
  }
}

/// Linear texel `index` of `p` (which must lie inside its texel bytes).
inline glm::vec4 paletteTexel(const BakedPalette& p, uint32_t index) {
  return formatTexel(p.format, p.texel_bytes.data(), index);
}

}  // namespace si::detail
