// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Composed layers' table and sizes (shaders/layer_compose.glsl): which palette slots of each
// mask the compose pass composes, where their rows go, and whether a frame's rows fit. No GL
// here.

#include <cstdint>
#include <vector>

#include "si/core/layer_mask.h"
#include "si/core/span.h"

namespace si::detail {

/// The compose table of `masks` (all of one palette, as a crowd's are): the palette slot count,
/// the row stride (the most masked slots of any mask), the mask count; then per mask each
/// slot's index among its masked slots in slot order (-1 outside the mask); then per mask its
/// masked slots in that order, -1 past its count up to the stride. {0, 0, 0} for no masks.
std::vector<int32_t> layerComposeTable(Span<const LayerMask> masks);

/// Bytes of a rows buffer for `records` composed records of `stride` masked slots: three
/// 16-byte rows per slot.
inline uint64_t composedRowBytes(uint64_t records, uint32_t stride) {
  return records * stride * 48;
}

/// Whether drawCrowd composes the layers of a frame whose layer block holds `records` records
/// (InstanceBatcher::layerBufferBound / kLayerRecordSize) of `stride` masked slots: rows of at
/// most `limit` bytes (GL_MAX_SHADER_STORAGE_BLOCK_SIZE) and at least one slot. Otherwise the
/// draws walk the chain per vertex (the layered programs), as with composing off.
inline bool composedRowsFit(uint64_t limit, uint64_t records, uint32_t stride) {
  return stride > 0 && composedRowBytes(records, stride) <= limit;
}

}  // namespace si::detail
