// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The compose table's buffer and the composed rows.
#include "gl/resources/layer_compose_buffers.h"

#include <algorithm>

#include "gl/resources/gl_allocation.h"

namespace si::detail {

Status LayerComposeBuffers::uploadTable(const std::vector<int32_t>& content) {
  return table.upload(content, 23, "composed layers: the compose table");
}

Status LayerComposeBuffers::ensureRows(uint64_t bytes, uint64_t limit, bool previous) {
  for (int k = 0; k < (previous ? 2 : 1); ++k) {
    if (rows[k] == kNoObject || bytes > row_bytes[k]) {
      // Geometric growth; never empty (GL refuses a buffer of no bytes).
      const uint64_t grown =
          std::max<uint64_t>({bytes, std::min(limit, row_bytes[k] + row_bytes[k] / 2), 48});
      row_bytes[k] = 0;
      const Status s = createBuffer(&rows[k], grown, nullptr, 0,
                                    k == 0 ? "composed layers: the composed rows"
                                           : "composed layers: the previous records' rows");
      if (!s.isOk()) return s;
      row_bytes[k] = grown;
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(26 + k), rows[k]);
  }
  return Status::ok();
}

void LayerComposeBuffers::bind(bool previous) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 23, table.buffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 26, rows[0]);
  if (previous) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 27, rows[1]);
}

void LayerComposeBuffers::release() {
  table.release();
  for (int k = 0; k < 2; ++k) {
    if (rows[k] != kNoObject) glDeleteBuffers(1, &rows[k]);
    rows[k] = kNoObject;
    row_bytes[k] = 0;
  }
}

}  // namespace si::detail
