// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The compose table of composed layers.
#include "crowd/layer_compose_table.h"

#include <algorithm>

namespace si::detail {

std::vector<int32_t> layerComposeTable(Span<const LayerMask> masks) {
  const size_t slots = masks.empty() ? 0 : masks[0].slot_anchor.size();
  int32_t stride = 0;
  for (const LayerMask& m : masks)
    stride = std::max<int32_t>(
        stride, int32_t(std::count_if(m.slot_anchor.begin(), m.slot_anchor.end(),
                                      [](int32_t a) { return a != LayerMask::kNotInMask; })));
  int32_t targets = 0;
  for (const LayerMask& m : masks)
    for (uint32_t t : m.morph_targets) targets = std::max(targets, int32_t(t) + 1);
  std::vector<int32_t> table{int32_t(slots), stride, int32_t(masks.size()), targets};
  table.reserve(4 + masks.size() * (slots + size_t(stride)));
  for (const LayerMask& m : masks) {
    int32_t next = 0;
    for (size_t slot = 0; slot < slots; ++slot)
      table.push_back(slot < m.slot_anchor.size() && m.slot_anchor[slot] != LayerMask::kNotInMask
                          ? next++
                          : -1);
  }
  for (const LayerMask& m : masks) {
    const size_t first = table.size();
    for (size_t slot = 0; slot < slots && slot < m.slot_anchor.size(); ++slot)
      if (m.slot_anchor[slot] != LayerMask::kNotInMask) table.push_back(int32_t(slot));
    table.resize(first + size_t(stride), -1);
  }
  return table;
}

}  // namespace si::detail
