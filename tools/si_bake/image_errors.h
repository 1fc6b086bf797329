// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// si-bake --image-errors: each LOD level's image error beside its geometric error, measured in
// an offscreen context of its own (si::HeadlessContext, si::measureImageLodErrors). Built only
// where the library has a headless back-end (SI_HEADLESS).
#include <cstdio>
#include <string>

#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/crowd/impostor_desc.h"

namespace si::tools {

/// Prints the table to `f`; false with `why` set when no context can be made or the
/// measurement fails. `character` must carry LOD errors (as printLodTable measures them). With
/// `impostor` not null (--impostor), an impostor level captured by that desc is appended and
/// measured too, every level between the impostor's captured views and frames.
bool printImageErrors(std::FILE* f, const Character& character, const BakedPalette& palette,
                      const ImpostorDesc* impostor, std::string* why);

}  // namespace si::tools
