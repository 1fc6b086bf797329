// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The baker's texel writer: a planned palette's frames evaluated by the reference and stored in
// the palette's format.
#include "si/bake/animation_baker.h"

namespace si::detail {

/// Bakes the planned clips into `out`: texels, clip table, joint maps and border frames (no
/// bounds). `desc` is resolved. Fails with kUnsupported naming the clip, joint and time when
/// kQuatTranslationF32 meets a joint with non-uniform or negative scale; `out` is then
/// untouched.
Status bakeTexels(const Character& character, const BakeDesc& desc, const PalettePlan& plan,
                  BakedPalette* out);

}  // namespace si::detail
