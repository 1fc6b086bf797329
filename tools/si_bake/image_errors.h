// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// si-bake --image-errors: each LOD level's image error beside its geometric error, measured in
// an offscreen context of its own (si::HeadlessContext, si::measureImageLodErrors). Built only
// where the library has a headless back-end (SI_HEADLESS).
#include <cstdio>
#include <string>

#include "si/core/baked_palette.h"
#include "si/core/character.h"

namespace si::tools {

/// Prints the table to `f`; false with `why` set when no context can be made or the
/// measurement fails. `character` must carry LOD errors (as printLodTable measures them). With
/// `impostor` (--impostor), an impostor level (si::ImpostorDesc's defaults) is appended and
/// measured too, every level between the impostor's captured views and frames.
bool printImageErrors(std::FILE* f, const Character& character, const BakedPalette& palette,
                      bool impostor, std::string* why);

}  // namespace si::tools
