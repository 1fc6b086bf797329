// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// si-bake's LOD table: triangles and geometric error per level, and with --image-errors each
// level's image error (image_errors.h, where the build has a headless back-end).
#include <cstdio>
#include <string>

#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/crowd/impostor_desc.h"

namespace si_bake {

/// Triangles and geometric error per LOD level as instances draw them (a sub-mesh with fewer
/// levels draws its last), in the bind pose and over poses of the clips; the errors are what
/// the crowd's screen-error LOD mode selects by (docs/crowd.md). Also the image errors with
/// `image_errors` (and, with `impostor` not null, the impostor's that desc captures); false
/// with `why` when they cannot be measured.
bool printLodTable(std::FILE* f, const si::Character& character, const si::BakedPalette& palette,
                   bool image_errors, const si::ImpostorDesc* impostor, std::string* why);

}  // namespace si_bake
