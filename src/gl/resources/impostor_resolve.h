// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// An impostor atlas captured supersampled (ImpostorDesc::capture_supersample): the capture
// drawn into a texture `factor` times the atlas's size each way, then averaged into the atlas's
// level 0 by a compute pass (shaders/impostor_resolve.comp.glsl). Averaged, the capture's
// whole-or-nothing texels become coverage: a spear thinner than a texel stays as a faint line
// instead of appearing in one view and vanishing in the next, and edges are antialiased, as
// the supersampled image they stand in for. At the captured views and frames, a factor of 2
// halves the pixels an 8-pixel impostor changes against the mesh (docs/accuracy.md).

#include <glad/gl.h>

#include <cstdint>

#include "si/core/status.h"

namespace si::detail {

/// Writes level 0 of `atlas` (`width` x `height` texels, 3 layers, RGBA8) from `capture` (the
/// same layers at `factor` times the size each way, one level) with `program`
/// (ProgramId::kImpostorResolve): each texel the mean of the capture texels it covers, then
/// generates the atlas's other levels from it, and writes layer 2 at level 0 again as one
/// material's: the largest code among those texels (codes are gathered unfiltered at level 0,
/// impostor.frag.glsl) and that material's mean values times the coverage (the other levels
/// keep the means their fallback divides by coverage).
/// Binds texture unit 0, image unit 0 and the program (the caller's state guard restores
/// them). kBackend naming the GL error.
Status resolveImpostorCapture(GLuint program, GLuint capture, GLuint atlas, uint32_t width,
                              uint32_t height, uint32_t factor);

}  // namespace si::detail
