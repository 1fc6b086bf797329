// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Blend spaces (si/crowd/blend_space.h): validation, the pair around a parameter, the period of
// a phase-synchronised blend.
#include "si/crowd/blend_space.h"

#include <algorithm>
#include <cmath>

#include "core/str_cat.h"

namespace si {
using detail::strCat;

Status BlendSpace::validate(const BakedPalette& palette, uint32_t mask_count) const {
  const auto bad = [&](const std::string& why) {
    return Status{StatusCode::kInvalidArgument, strCat("blend space '", name, "': ", why)};
  };
  if (name.empty()) return {StatusCode::kInvalidArgument, "blend space: it has no name"};
  if (clips.size() < 2 || clips.size() > kMaxBlendClips)
    return bad(strCat(clips.size(), " clips; a blend space holds 2 to ", kMaxBlendClips));
  if (!is2D() && positions.size() != clips.size())
    return bad(strCat(positions.size(), " positions for ", clips.size(), " clips"));
  if (is2D() && (positions.size() < 2 || positions_y.size() < 2 ||
                 positions.size() * positions_y.size() != clips.size()))
    return bad(strCat("a 2D grid of ", positions.size(), " x ", positions_y.size(), " lines for ",
                      clips.size(),
                      " clips; it needs at least 2 x 2 lines, a clip for each point"));
  for (size_t k = 0; k < clips.size(); ++k)
    if (clips[k] >= palette.clips.size())
      return bad(
          strCat("clip ", k, " is ", clips[k], ", past the palette's ", palette.clips.size()));
  const auto increasing = [&](const std::vector<float>& lines, const char* what) -> std::string {
    for (size_t k = 0; k < lines.size(); ++k) {
      if (!std::isfinite(lines[k])) return strCat(what, " ", k, " is not finite");
      if (k > 0 && !(lines[k] > lines[k - 1]))
        return strCat(what, " ", k, " (", lines[k], ") is not above ", what, " ", k - 1, " (",
                      lines[k - 1], ")");
    }
    return {};
  };
  std::string why = increasing(positions, "position");
  if (why.empty()) why = increasing(positions_y, "y position");
  if (!why.empty()) return bad(why);
  if (mask >= mask_count)
    return bad(strCat("mask ", mask, " is past the crowd's ", mask_count, " (addLayerMask)"));
  return Status::ok();
}

BlendPair blendPair(const std::vector<float>& positions, float parameter) {
  BlendPair p;
  const uint32_t n = uint32_t(positions.size());
  if (n < 2) return p;
  if (!(parameter > positions[0])) {  // At or below the first, or NaN.
    p.upper = 1;
    return p;
  }
  uint32_t upper = 1;
  while (upper + 1 < n && parameter > positions[upper]) ++upper;
  p.lower = upper - 1;
  p.upper = upper;
  const float span = positions[upper] - positions[upper - 1];
  const float w = (parameter - positions[upper - 1]) / span;
  p.weight = w < 1.0f ? w : 1.0f;
  return p;
}

BlendPoint blendPoint(const BlendSpace& space, float x, float y) {
  BlendPoint b;
  const BlendPair px = blendPair(space.positions, x);
  if (!space.is2D()) {
    b.count = 2;
    b.clips[0] = px.lower;
    b.clips[1] = px.upper;
    b.shares[0] = 1.0f - px.weight;
    b.shares[1] = px.weight;
    b.chain[1] = px.weight;
  } else {
    const BlendPair py = blendPair(space.positions_y, y);
    const uint32_t nx = uint32_t(space.positions.size());
    const float u = px.weight, v = py.weight;
    b.count = 4;
    b.clips[0] = py.lower * nx + px.lower;
    b.clips[1] = py.lower * nx + px.upper;
    b.clips[2] = py.upper * nx + px.lower;
    b.clips[3] = py.upper * nx + px.upper;
    b.shares[0] = (1.0f - u) * (1.0f - v);
    b.shares[1] = u * (1.0f - v);
    b.shares[2] = (1.0f - u) * v;
    b.shares[3] = u * v;
    // shares[k] over the sum of shares 0..k: u, (1 - u) v / (1 - u v), u v.
    b.chain[1] = u;
    const float rest = 1.0f - u * v;
    b.chain[2] = rest > 0.0f ? std::min(b.shares[2] / rest, 1.0f) : 0.0f;
    b.chain[3] = b.shares[3];
  }
  b.chain[0] = 1.0f;
  return b;
}

double blendPeriod(double lower_seconds, double upper_seconds, float weight) {
  return lower_seconds + (upper_seconds - lower_seconds) * double(weight);
}

}  // namespace si
