// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Writing the palette file (a baked palette as a versioned little-endian binary, so baking can
/// be a preprocessing step and the runtime only loads; docs/palette-format.md specifies the
/// bytes) and the file helpers of the offline tools. Reading is runtime code:
/// si/core/palette_file.h (loadPalette), included here.
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
#include "si/core/palette_file.h"
#include "si/core/span.h"

namespace si {

/// Serializes `palette` into `bytes` (replacing its contents). Fails with kInvalidArgument for a
/// null output or a palette that fails BakedPalette::validate() (its message included): no file
/// is written that loadPalette() would refuse.
Status savePalette(const BakedPalette& palette, std::vector<uint8_t>* bytes);

/// savePalette() to a file; kIo naming the path when it cannot be written.
Status savePaletteFile(const BakedPalette& palette, const std::string& path);
/// loadPalette() (si::core) from a file; kIo naming the path when it cannot be read,
/// kLimitExceeded past kMaxPaletteFileSize.
Status loadPaletteFile(const std::string& path, BakedPalette* palette);

}  // namespace si
