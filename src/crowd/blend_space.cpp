// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Blend spaces (si/crowd/blend_space.h): validation, the pair around a parameter, the period of
// a phase-synchronised blend.
#include "si/crowd/blend_space.h"

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
  if (positions.size() != clips.size())
    return bad(strCat(positions.size(), " positions for ", clips.size(), " clips"));
  for (size_t k = 0; k < clips.size(); ++k) {
    if (clips[k] >= palette.clips.size())
      return bad(
          strCat("clip ", k, " is ", clips[k], ", past the palette's ", palette.clips.size()));
    if (!std::isfinite(positions[k])) return bad(strCat("position ", k, " is not finite"));
    if (k > 0 && !(positions[k] > positions[k - 1]))
      return bad(strCat("position ", k, " (", positions[k], ") is not above position ", k - 1, " (",
                        positions[k - 1], ")"));
  }
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

double blendPeriod(double lower_seconds, double upper_seconds, float weight) {
  return lower_seconds + (upper_seconds - lower_seconds) * double(weight);
}

}  // namespace si
