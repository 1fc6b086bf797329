// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A level's measured curve (si::ImageLodLevel::mean_differing_pixels): the pixels of one
// character's image it changes at each measured height, read on a log-log scale between the
// measurements around a height and along the nearest two past them (in proportion to the
// height from one). measureImageLodErrors derives the one-pixel height from it, the hand-over
// (image_lod_units.cpp) compares two levels' curves.
#include <cstdint>
#include <vector>

namespace si::detail {

/// The height at which `differing` (per height in `heights`, any order) reaches one pixel;
/// infinite when nothing differs; where the curve is flat, the nearest measured end.
double onePixelHeight(const std::vector<uint32_t>& heights, const std::vector<double>& differing);

/// `differing` (per height in `heights`) at `height` pixels; 0 where nothing differs.
double differingAt(const std::vector<uint32_t>& heights, const std::vector<double>& differing,
                   double height);

}  // namespace si::detail
