// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A level's measured curve (image_lod_curve.h): differing pixels against height, read on a
// log-log scale.
#include "gl/image_lod_curve.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace si::detail {

namespace {

// The measurements of `differing` (per height) where something differs, as natural logarithms
// of the height (x) and of the differing pixels (y), by increasing height.
void logCurve(const std::vector<uint32_t>& heights, const std::vector<double>& differing,
              std::vector<double>* x, std::vector<double>* y) {
  std::vector<size_t> order(heights.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return heights[a] < heights[b]; });
  for (size_t k : order)
    if (differing[k] > 0.0) {
      x->push_back(std::log(double(heights[k])));
      y->push_back(std::log(differing[k]));
    }
}

}  // namespace

double onePixelHeight(const std::vector<uint32_t>& heights, const std::vector<double>& differing) {
  std::vector<double> x, y;
  logCurve(heights, differing, &x, &y);
  if (x.empty()) return std::numeric_limits<double>::infinity();
  if (x.size() == 1) return std::exp(x[0] - y[0]);  // In proportion to the height.
  size_t i = 0;  // The segment [i, i + 1] around log 1 = 0, or the nearest end one.
  while (i + 2 < x.size() && y[i + 1] < 0.0) ++i;
  const double slope = (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
  if (!(slope > 0.0)) return std::exp(y[i + 1] < 0.0 ? x.back() : x[0]);  // Flat: no crossing.
  return std::exp(x[i] - y[i] / slope);
}

double differingAt(const std::vector<uint32_t>& heights, const std::vector<double>& differing,
                   double height) {
  std::vector<double> x, y;
  logCurve(heights, differing, &x, &y);
  if (x.empty()) return 0.0;
  const double at = std::log(height);
  if (x.size() == 1) return std::exp(y[0] + at - x[0]);
  size_t i = 0;  // The segment [i, i + 1] around `at`, or the nearest end one.
  while (i + 2 < x.size() && x[i + 1] < at) ++i;
  const double slope = (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
  return std::exp(y[i] + slope * (at - x[i]));
}

}  // namespace si::detail
