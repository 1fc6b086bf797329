// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The covered rectangle of every impostor cell at every mip level, read back from the atlas.
#include "gl/resources/impostor_coverage.h"

#include <algorithm>
#include <cmath>

#include "gl/resources/atlas_bands.h"

namespace si::detail {

namespace {

// Per texel column (or row) of a level: the first and last cell it overlaps, and its edges in
// level-0 texels.
struct TexelSpan {
  uint32_t first_cell, last_cell;
  double low, high;
};

std::vector<TexelSpan> texelSpans(uint32_t level_texels, uint32_t base_texels, uint32_t cell,
                                  uint32_t cells) {
  std::vector<TexelSpan> spans(level_texels);
  const double scale = double(base_texels) / double(level_texels);
  for (uint32_t t = 0; t < level_texels; ++t) {
    TexelSpan& s = spans[t];
    s.low = double(t) * scale;
    s.high = double(t + 1) * scale;
    s.first_cell = std::min(uint32_t(s.low / cell), cells - 1);
    s.last_cell = std::min(uint32_t(std::ceil(s.high / cell)) - 1, cells - 1);
  }
  return spans;
}

uint32_t quantize(double fraction, bool up) {
  const double q = up ? std::ceil(fraction * 255.0) + 1.0 : std::floor(fraction * 255.0) - 1.0;
  return uint32_t(std::clamp(q, 0.0, 255.0));
}

// An extent in level-0 texels from a cell's lower left corner.
struct Extent {
  double left = 1e30, bottom = 1e30, right = -1e30, top = -1e30;
  void add(double l, double b, double r, double t) {
    left = std::min(left, l);
    bottom = std::min(bottom, b);
    right = std::max(right, r);
    top = std::max(top, t);
  }
};

// A cell at one level: the texels of any coverage, and those of at least half (127: a filter
// rounding up by one step stays covered).
struct CellExtents {
  Extent any, half;
};
constexpr uint8_t kHalf = 127;

}  // namespace

uint32_t packCoveredRect(double left, double bottom, double right, double top) {
  if (!(right > left && top > bottom)) return 0;
  return quantize(left, false) | quantize(bottom, false) << 8 | quantize(right, true) << 16 |
         quantize(top, true) << 24;
}

Status measureCoveredRects(GLuint atlas, uint32_t columns, uint32_t rows, uint32_t cell,
                           uint32_t levels, std::vector<uint32_t>* rects) {
  const uint32_t cells = columns * rows;
  const uint32_t width = columns * cell, height = rows * cell;
  rects->assign(size_t(cells) * levels, 0u);
  std::vector<CellExtents> extents;
  for (uint32_t level = 0; level < levels; ++level) {
    const uint32_t w = std::max(width >> level, 1u), h = std::max(height >> level, 1u);
    const std::vector<TexelSpan> xs = texelSpans(w, width, cell, columns);
    const std::vector<TexelSpan> ys = texelSpans(h, height, cell, rows);
    extents.assign(cells, CellExtents());
    const Status s = readLayerBands(
        atlas, GLint(level), 0, w, h, "buildImpostor: reading the atlas's coverage back",
        [&](uint32_t y0, uint32_t n, const uint8_t* band) {
          for (uint32_t j = 0; j < n; ++j) {
            const TexelSpan& y = ys[y0 + j];
            const uint8_t* row = band + size_t(j) * w * 4;
            for (uint32_t x = 0; x < w; ++x) {
              if (row[size_t(x) * 4 + 3] == 0) continue;
              const TexelSpan& sx = xs[x];
              const bool half = row[size_t(x) * 4 + 3] >= kHalf;
              // A texel's centre +- one texel: where the filter can weigh it.
              const double dx = 0.5 * (sx.high - sx.low), dy = 0.5 * (y.high - y.low);
              for (uint32_t cy = y.first_cell; cy <= y.last_cell; ++cy)
                for (uint32_t cx = sx.first_cell; cx <= sx.last_cell; ++cx) {
                  CellExtents& e = extents[size_t(cy) * columns + cx];
                  const double l = sx.low - double(cx) * cell, b = y.low - double(cy) * cell;
                  const double r = sx.high - double(cx) * cell, t = y.high - double(cy) * cell;
                  e.any.add(l, b, r, t);
                  if (half) e.half.add(l - dx, b - dy, r + dx, t + dy);
                }
            }
          }
          return true;
        });
    if (!s.isOk()) return s;
    // Bilinear filtering passes one half only within a texel of a texel of at least half, and
    // only within the texels of any coverage (past them it weighs them by one half at most).
    for (uint32_t c = 0; c < cells; ++c) {
      const CellExtents& e = extents[c];
      (*rects)[size_t(c) * levels + level] = packCoveredRect(
          std::max(e.any.left, e.half.left) / cell, std::max(e.any.bottom, e.half.bottom) / cell,
          std::min(e.any.right, e.half.right) / cell, std::min(e.any.top, e.half.top) / cell);
    }
  }
  return Status::ok();
}

}  // namespace si::detail
