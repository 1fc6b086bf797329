// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the palette file's reader (si::core, loadPalette) and writer (si::bake, savePalette)
// share: the magic, the format's limits and the byte order check (docs/palette-format.md).

#include <cstdint>
#include <cstring>

namespace si::detail {

inline constexpr char kPaletteMagic[8] = {'S', 'I', 'P', 'A', 'L', 'E', 'T', 0};
inline constexpr uint32_t kMaxPaletteNameLength = 4096;
inline constexpr uint32_t kMaxPaletteTextureSize = 32768;

/// The format is little-endian; so are the hosts this library supports.
inline bool isLittleEndian() {
  const uint32_t one = 1;
  uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

}  // namespace si::detail
