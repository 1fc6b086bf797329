// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Morph entries ordered by effect, with the bound on what the rest of a vertex's run moves it
// (see morph_entries.h).
#include "core/morph_entries.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/palette_texel.h"

namespace si::detail {

std::vector<float> morphWeightBounds(const BakedPalette& palette) {
  const PaletteLayout& layout = palette.layout;
  std::vector<float> bounds(layout.morph_target_count, 0.0f);
  if (bounds.empty()) return bounds;
  const int64_t border = int64_t(layout.border_frames);
  for (uint32_t c = 0; c < layout.clip_frame_count.size(); ++c) {
    const bool cubic =
        c < palette.clips.size() && palette.clips[c].interpolation == FrameInterpolation::kCubic;
    for (int64_t f = -border; f < int64_t(layout.clip_frame_count[c]) + border; ++f)
      for (uint32_t t = 0; t < layout.morph_target_count; t += 4) {
        const glm::vec4 w = paletteTexel(palette, layout.morphTexel(c, f, t));
        for (uint32_t k = 0; k < 4 && t + k < bounds.size(); ++k)
          bounds[t + k] = std::max(bounds[t + k], std::fabs(w[int(k)]) * (cubic ? 1.25f : 1.0f));
      }
  }
  return bounds;
}

uint32_t morphTailBits(float tail) {
  if (!(tail > 0.0f)) return 0u;  // Zero (and, defensively, NaN) moves nothing.
  if (!(tail <= std::numeric_limits<float>::max())) return 0x7F800000u;  // +infinity.
  uint32_t bits;
  std::memcpy(&bits, &tail, sizeof bits);
  const uint32_t upper = bits & 0xFFFF0000u;
  // Rounded up: a positive float's bits grow with its value (the largest finite rounds to
  // +infinity, which still bounds it).
  return upper == bits ? upper : upper + 0x10000u;
}

std::vector<float> orderMorphEntriesByEffect(const SkinnedMesh& mesh,
                                             const std::vector<float>& weight_bounds,
                                             MorphEntriesByVertex* by_vertex) {
  using Entry = MorphEntriesByVertex::Entry;
  const auto effect = [&](const Entry& e) {
    const float bound = e.target < weight_bounds.size() ? weight_bounds[e.target] : 0.0f;
    return glm::length(mesh.morph_targets[e.target].position_deltas[e.index]) * bound;
  };
  std::vector<float> tails(by_vertex->entries.size(), 0.0f);
  for (size_t v = 0; v + 1 < by_vertex->first.size(); ++v) {
    const auto begin = by_vertex->entries.begin() + by_vertex->first[v];
    const auto end = by_vertex->entries.begin() + by_vertex->first[v + 1];
    std::stable_sort(begin, end,
                     [&](const Entry& a, const Entry& b) { return effect(a) > effect(b); });
    double sum = 0.0;  // In double, then rounded up: never below the float sum's value.
    for (uint32_t i = by_vertex->first[v + 1]; i > by_vertex->first[v]; --i) {
      sum += double(effect(by_vertex->entries[i - 1]));
      float tail = float(sum);
      if (double(tail) < sum) tail = std::nextafter(tail, std::numeric_limits<float>::infinity());
      tails[i - 1] = morphTailOfWord(morphTailBits(tail));
    }
  }
  return tails;
}

}  // namespace si::detail
