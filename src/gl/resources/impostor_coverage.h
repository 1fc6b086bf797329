// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What each impostor cell covers: per cell and mip level of the atlas, the rectangle of the cell
// outside which that level's bilinear coverage is below one half, which the fragment stage
// discards (impostor.frag.glsl). Trilinear filtering passes one half only where one of its two
// levels does, so the impostor vertex shader draws the union of the rectangles of the levels its
// fragments can sample (impostor.vert.glsl): the quads shade what can pass the coverage test
// and nothing around it, the image unchanged. A cell none of whose texels at those levels is
// half covered draws no quad.

#include <glad/gl.h>

#include <cstdint>
#include <vector>

#include "si/core/status.h"

namespace si::detail {

/// A cell's covered rectangle in 8-bit fractions of its side, from its lower left corner:
/// bits 0-7 the left edge, 8-15 the bottom, 16-23 the right, 24-31 the top; each rounded
/// outwards by one 255th more. 0 (an empty rectangle) for a cell with no coverage.
uint32_t packCoveredRect(double left, double bottom, double right, double top);

/// Reads layer 0 (the coverage in alpha) of `atlas` (`columns` x `rows` cells of `cell` texels
/// at level 0, `levels` mip levels) back level by level, in bands of at most 16 MiB, and fills
/// `rects` with packCoveredRect() of every cell at every level: cell c, level l at
/// c * levels + l (cell c at column c % columns, row c / columns from the bottom). The
/// rectangle is the intersection of the texels of any coverage and the texels within one texel
/// of a texel at least half covered (a sample of less than half covered texels around it
/// filters to less than half; one past the covered texels, to half at most). A texel of a
/// coarse level that straddles two cells counts for both. Needs the default pixel-pack state
/// (GlStateGuard's readback footprint).
Status measureCoveredRects(GLuint atlas, uint32_t columns, uint32_t rows, uint32_t cell,
                           uint32_t levels, std::vector<uint32_t>* rects);

}  // namespace si::detail
