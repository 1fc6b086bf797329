// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Loading a baked palette at run time: the palette file (docs/palette-format.md specifies the
/// bytes) parsed from memory. Runtime code, in si::core: a game that only loads and draws
/// palettes links si::core, si::crowd and si::gl, not the baker. The file's bytes come from the
/// host's own file system; the writer and the file helpers of the offline tools are in
/// si/bake/palette_file.h.
///
/// Usage:
/// \code
///   std::vector<uint8_t> bytes = engine.readFile("soldier.sipal");
///   si::BakedPalette palette;
///   si::Status s = si::loadPalette(bytes, &palette);
/// \endcode

#include <cstdint>

#include "si/core/baked_palette.h"
#include "si/core/span.h"
#include "si/core/status.h"

namespace si {

/// The version si::savePalette() writes (6: each palette joint's bounds follow the joint table).
/// loadPalette() reads it, version 5 (no joint bounds), version 4 (no morph targets), version 3
/// (no root motion), version 2 (no markers) and version 1 (linear clips, no border frames: the
/// files written before cubic interpolation).
inline constexpr uint32_t kPaletteFileVersion = 6;
/// Largest palette file loadPalette() accepts (1 GiB).
inline constexpr uint64_t kMaxPaletteFileSize = uint64_t(1) << 30;

/// Parses a palette file. Every count and offset is checked against the bytes left before it
/// is used; on any failure `palette` is untouched and the status names what was wrong:
/// kCorrupt for a bad magic, truncation, trailing bytes, a checksum mismatch, a value outside
/// its range, a clip table or layout inconsistent with the header, or a palette that fails
/// BakedPalette::validate() (whose message follows "palette file: "): a loaded palette is as
/// consistent as a fresh bake. kUnsupported for a version other than 1 to 6 or a big-endian
/// host; kLimitExceeded for more than kMaxPaletteFileSize bytes; kInvalidArgument for a null
/// `palette`.
Status loadPalette(Span<const uint8_t> bytes, BakedPalette* palette);

/// CRC-32 (IEEE 802.3, reflected, as zlib computes it) of `bytes`: the palette file's checksum.
uint32_t crc32(Span<const uint8_t> bytes);

}  // namespace si
