// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Composed layers' table and sizes (src/gl/shaders/layer_compose.glsl): which palette slots of
// each mask the compose pass composes, where their rows go, and whether a frame's rows fit.
// API-free: si::gl's compose pass and si::vk's use it.

#include <cstdint>
#include <vector>

#include "si/core/layer_mask.h"
#include "si/core/span.h"

namespace si::detail {

/// The compose table of `masks` (all of one palette, as a crowd's are): the palette slot count,
/// the row stride (the most masked slots of any mask), the mask count, the composed morph
/// targets (past the highest target any mask holds; 0 when none holds one); then per mask each
/// slot's index among its masked slots in slot order (-1 outside the mask); then per mask its
/// masked slots in that order, -1 past its count up to the stride. {0, 0, 0, 0} for no masks.
std::vector<int32_t> layerComposeTable(Span<const LayerMask> masks);

/// What the compose pass writes per composed record (layer_compose.glsl): the rows of `stride`
/// masked slots (three 16-byte rows each), then the weights of the first `morph_targets` morph
/// targets (floats, in 16-byte groups of four).
struct ComposeShape {
  uint32_t stride = 0;
  uint32_t morph_targets = 0;

  /// Bytes per composed record.
  uint64_t recordBytes() const { return uint64_t(stride) * 48 + (morph_targets + 3) / 4 * 16; }
  /// Invocations per composed record: one per masked slot (each also writes every lanes()-th
  /// weight), one when the masks hold targets only; 0 when there is nothing to compose.
  uint32_t lanes() const { return stride > 0 ? stride : (morph_targets > 0 ? 1 : 0); }
};

/// The shape of compose table `table` (layerComposeTable).
inline ComposeShape composeShape(const std::vector<int32_t>& table) {
  return {uint32_t(table[1]), uint32_t(table[3])};
}

/// Bytes of a rows buffer for `records` composed records of `shape`.
inline uint64_t composedRowBytes(uint64_t records, const ComposeShape& shape) {
  return records * shape.recordBytes();
}

/// Whether drawCrowd composes the layers of a frame whose layer block holds `records` records
/// (InstanceBatcher::layerBufferBound / kLayerRecordSize) of `shape`: rows of at most `limit`
/// bytes (GL_MAX_SHADER_STORAGE_BLOCK_SIZE) and something to compose. Otherwise the draws walk
/// the chain per vertex (the layered programs), as with composing off.
inline bool composedRowsFit(uint64_t limit, uint64_t records, const ComposeShape& shape) {
  return shape.lanes() > 0 && composedRowBytes(records, shape) <= limit;
}

}  // namespace si::detail
