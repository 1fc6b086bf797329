// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A report's errors made the crowd's (CrowdDesc::lod_errors_units): levels selected by their
// image errors, or by their geometric errors with the impostor handed over where its measured
// curve rises above the mesh levels'.
#include <algorithm>
#include <cmath>

#include "gl/image_lod_curve.h"
#include "si/gl/image_lod_error.h"

namespace si {

using detail::differingAt;

namespace {

// The tallest height (pixels) up to which the impostor (the report's last level) changes no
// more pixels than the mesh level the screen-error choice at `budget` pixels draws there by
// `units` (the coarsest of levels 1 to n - 2 whose error projects within the budget), the
// curves read by differingAt, stepping up from 1 pixel by 1/16 of an octave to the first height
// it loses at, then bisecting: 0 where it loses at 1 pixel; LOD 1's tallest height (or 16 times
// the tallest measured) where it never does.
double impostorHandoverHeight(const std::vector<float>& units, const ImageLodErrorReport& report,
                              double budget) {
  const size_t n = units.size();
  const double height_units = report.character_height_units;
  const std::vector<uint32_t>& heights = report.heights_pixels;
  const double ceiling = 16.0 * double(*std::max_element(heights.begin(), heights.end()));
  // Whether the impostor changes at most as many pixels as the mesh level drawn at `h` (false
  // past LOD 1's range, where LOD 0 is drawn, and past the ceiling).
  const auto wins = [&](double h) {
    size_t l = n - 2;
    while (l >= 1 && double(units[l]) * h > budget * height_units) --l;
    if (l == 0 || h > ceiling) return false;
    return differingAt(heights, report.levels.back().mean_differing_pixels, h) <=
           differingAt(heights, report.levels[l].mean_differing_pixels, h);
  };
  if (!wins(1.0)) return 0.0;
  double lo = 1.0, hi = 1.0;
  for (;;) {  // Up by 1/16 of an octave to the first height it loses at...
    hi = lo * 1.0442737824274138;
    if (!wins(hi)) break;
    lo = hi;
  }
  for (int k = 0; k < 40; ++k) {  // ...then the boundary by bisection.
    const double mid = 0.5 * (lo + hi);
    (wins(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

std::vector<float> imageLodErrorsUnits(const ImageLodErrorReport& report) {
  std::vector<float> out;
  for (const ImageLodLevel& level : report.levels)
    out.push_back(out.empty() ? 0.0f : std::max(out.back(), level.image_units));
  if (report.impostor && out.size() > 1) {  // Levels the impostor dominates take its error.
    const float impostor = report.levels.back().image_units;
    for (size_t l = 1; l + 1 < out.size(); ++l) out[l] = std::min(out[l], impostor);
    out.back() = std::max(impostor, out[out.size() - 2]);
  }
  return out;
}

std::vector<float> impostorLodErrorsUnits(const std::vector<float>& geometric_units,
                                          const ImageLodErrorReport& report, float budget_pixels) {
  std::vector<float> out = geometric_units;
  const size_t n = out.size();
  if (!report.impostor || n < 2 || report.levels.size() != n) return out;
  const double budget =
      budget_pixels > 0.0f && std::isfinite(budget_pixels) ? double(budget_pixels) : 1.0;
  const ImageLodLevel& impostor = report.levels.back();
  bool curves = n > 2 && !report.heights_pixels.empty() && report.character_height_units > 0.0f;
  for (const ImageLodLevel& level : report.levels)
    curves = curves && level.mean_differing_pixels.size() == report.heights_pixels.size();
  float handover = 0.0f;
  if (curves) {
    // Where the search stopped at the end of a level's characters, the bisection's last
    // height lies within float rounding of it: the float is that level's error.
    const double units =
        budget * report.character_height_units / impostorHandoverHeight(out, report, budget);
    handover = units <= double(out[n - 2])
                   ? float(units)
                   : std::max(out[n - 2], float(std::min(units, double(impostor.image_units))));
  } else {  // One number per level: the trailing levels whose one-pixel error exceeds its own.
    size_t first = n - 1;
    while (first > 1 && report.levels[first - 1].image_units > impostor.image_units) --first;
    handover = first < n - 1 ? out[first] : std::max(out[n - 2], impostor.image_units);
  }
  for (size_t l = 1; l + 1 < n; ++l) out[l] = std::min(out[l], handover);
  out[n - 1] = handover;
  return out;
}

}  // namespace si
