// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Composed layers' buffers (shaders/layer_compose.glsl): the compose table
// (layer_compose_table.h) and the rows the compose pass writes for this frame's records (and
// their previous records) and the vertex shaders read.

#include <glad/gl.h>

#include <cstdint>
#include <vector>

#include "crowd/layer_compose_table.h"
#include "gl/programs/program_set.h"
#include "gl/resources/gl_allocation.h"
#include "si/core/status.h"

namespace si::detail {

struct LayerComposeBuffers {
  TableBuffer table;
  /// This frame's records' rows; the previous records' (motion vectors only).
  GLuint rows[2] = {kNoObject, kNoObject};
  uint64_t row_bytes[2] = {0, 0};  ///< Their sizes.

  /// Makes `table` hold `content` (TableBuffer::upload) and binds it at storage binding 23.
  Status uploadTable(const std::vector<int32_t>& content);
  /// Makes the rows buffer (both with `previous`) hold at least `bytes`, grown geometrically
  /// up to `limit` (GL_MAX_SHADER_STORAGE_BLOCK_SIZE; `bytes` is at most that), and binds them at
  /// storage bindings 26 and 27. kLimitExceeded (createBuffer) when the driver has no memory.
  Status ensureRows(uint64_t bytes, uint64_t limit, bool previous);
  /// Binds the table and the rows (the previous records' too with `previous`) again.
  void bind(bool previous) const;
  void release();
};

}  // namespace si::detail
