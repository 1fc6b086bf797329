// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Whether an impostor atlas's surface layer (layer 2: metallic, roughness, occlusion and the
// material's code, impostor_capture_material.glsl) holds one value wherever the character was
// drawn. A character of one material without metallic-roughness or occlusion textures (the
// embedded character, most crowd characters) captures one value there; its impostor fragments
// then take it from a uniform instead of reading the layer and gathering its codes (two texture
// reads of four: at 100k impostors of a few pixels, the fragment stage's reads bound the
// frame, docs/performance.md, "Impostors that read two layers").

#include <glad/gl.h>

#include <cstdint>

#include "si/core/status.h"

namespace si::detail {

/// Reads layer 2 of `capture` (`width` x `height` texels at level 0, RGBA8: the atlas, or its
/// supersampled capture, where every texel is drawn whole) back in bands of at most 16 MiB and
/// sets `*uniform` to its texel (R | G << 8 | B << 16 | A << 24) when every texel the capture
/// drew (alpha, the code, not 0) holds the same four bytes, else to 0 (the layer varies, or
/// nothing was drawn). Needs the default pixel-pack state (GlStateGuard's readback footprint).
Status measureUniformSurface(GLuint capture, uint32_t width, uint32_t height, uint32_t* uniform);

}  // namespace si::detail
