// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "gl/paths/live_palette.h"

#include <cstring>

#include "si/crowd/crowd_export.h"

namespace si::detail {

const BakedPalette& LivePalette::of(const BakedPalette& palette, const CrowdManager& crowd) {
  const CrowdExport live(crowd);
  const Span<const uint8_t> texels = live.livePoseTexels();
  if (texels.empty()) return palette;
  const size_t texel_bytes = bytesPerTexel(palette.format);
  const size_t at = size_t(live.livePoseFirstTexel()) * texel_bytes;
  if (source_ != &palette || palette_bytes_ != at ||
      copy_.texel_bytes.size() != at + texels.size()) {
    copy_ = palette;  // Once per palette (and when the crowd's room for poses differs).
    copy_.texel_bytes.resize(at + texels.size());
    source_ = &palette;
    palette_bytes_ = at;
    held_.forget();
  }
  uint32_t first = 0, count = 0;
  if (held_.update(live, crowd.identity(), &first, &count) && count > 0)
    std::memcpy(copy_.texel_bytes.data() + at + size_t(first) * texel_bytes,
                texels.data() + size_t(first) * texel_bytes, size_t(count) * texel_bytes);
  return copy_;
}

}  // namespace si::detail
