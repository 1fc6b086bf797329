// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The palette file: a baked palette as a versioned little-endian binary, so baking can be a
/// preprocessing step and the runtime only loads. docs/palette-format.md specifies the bytes.
///
/// Usage:
/// \code
///   std::vector<uint8_t> bytes;
///   si::Status s = si::savePalette(palette, &bytes);         // or savePaletteFile(palette, path)
///   si::BakedPalette loaded;
///   s = si::loadPalette(bytes, &loaded);                      // or loadPaletteFile(path, &loaded)
/// \endcode

#include <cstdint>
#include <string>
#include <vector>

#include "si/bake/animation_baker.h"
#include "si/core/span.h"

namespace si {

/// The version savePalette() writes (4: clips carry their root motion). loadPalette() reads
/// it, version 3 (no root motion), version 2 (no markers) and version 1 (linear clips, no border
/// frames: the files written before cubic interpolation).
inline constexpr uint32_t kPaletteFileVersion = 4;
/// Largest palette file loadPalette() accepts (1 GiB).
inline constexpr uint64_t kMaxPaletteFileSize = uint64_t(1) << 30;

/// Serializes `palette` into `bytes` (replacing its contents). Fails with kInvalidArgument for a
/// null output or a palette that fails BakedPalette::validate() (its message included): no file
/// is written that loadPalette() would refuse.
Status savePalette(const BakedPalette& palette, std::vector<uint8_t>* bytes);

/// Parses a palette file. Every count and offset is checked against the bytes left before it
/// is used; on any failure `palette` is untouched and the status names what was wrong:
/// kCorrupt for a bad magic, truncation, trailing bytes, a checksum mismatch, a value outside
/// its range, a clip table or layout inconsistent with the header, or a palette that fails
/// BakedPalette::validate() (whose message follows "palette file: "): a loaded palette is as
/// consistent as a fresh bake. kUnsupported for a version other than 1 to 4; kLimitExceeded
/// for more than kMaxPaletteFileSize bytes.
Status loadPalette(Span<const uint8_t> bytes, BakedPalette* palette);

/// savePalette() to a file; kIo naming the path when it cannot be written.
Status savePaletteFile(const BakedPalette& palette, const std::string& path);
/// loadPalette() from a file; kIo naming the path when it cannot be read.
Status loadPaletteFile(const std::string& path, BakedPalette* palette);

/// CRC-32 (IEEE 802.3, reflected, as zlib computes it) of `bytes`.
uint32_t crc32(Span<const uint8_t> bytes);

}  // namespace si
