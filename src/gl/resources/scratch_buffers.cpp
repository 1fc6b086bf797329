// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The draw paths' shared scratch buffers.
#include "gl/resources/scratch_buffers.h"

#include "gl/resources/gl_allocation.h"

namespace si::detail {

Status VertexRing::ensure(uint64_t wanted, bool exact, const char* what) {
  if (buffer != kNoObject && (exact ? vertices == wanted : vertices >= wanted))
    return Status::ok();
  vertices = 0;
  Status s = createBuffer(&buffer, wanted * 16, nullptr, 0, what);
  if (s.isOk()) vertices = wanted;
  return s;
}

void VertexRing::release() {
  if (buffer != kNoObject) glDeleteBuffers(1, &buffer);
  buffer = kNoObject;
  vertices = 0;
}

Status ScratchBuffers::uploadMaskTable(const std::vector<int32_t>& table) {
  // A new buffer whenever the table changes (another crowd's masks): draws issued before may
  // still read the old one, which GL keeps until they are done. Rewriting it in place raced
  // with them on the H100's driver (the second of two crowds' tables read by the first's draws),
  // flushing first or not.
  if (mask_table == kNoObject || table != mask_table_content) {
    mask_table_content.clear();
    const Status s = createBuffer(&mask_table, table.size() * sizeof(int32_t), table.data(), 0,
                                  "layered animation: the mask table");
    if (!s.isOk()) return s;
    mask_table_content = table;
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, mask_table);
  return Status::ok();
}

void ScratchBuffers::release() {
  if (mask_table != kNoObject) glDeleteBuffers(1, &mask_table);
  mask_table = kNoObject;
  mask_table_content.clear();
  layer_compose.release();
  compute_ring.release();
  compute_previous_ring.release();
  gpu_driven_ring.release();
  gpu_driven_previous_ring.release();
  if (cpu_stream != kNoObject) glDeleteBuffers(1, &cpu_stream);
  cpu_stream = kNoObject;
  cpu_stream_bytes = 0;
}

}  // namespace si::detail
