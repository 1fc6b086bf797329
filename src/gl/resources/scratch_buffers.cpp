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
  const size_t bytes = table.size() * sizeof(int32_t);
  if (mask_table == kNoObject || mask_table_bytes < bytes) {
    if (mask_table != kNoObject) glDeleteBuffers(1, &mask_table);
    mask_table_bytes = 0;
    const Status s = createBuffer(&mask_table, bytes, nullptr, GL_DYNAMIC_STORAGE_BIT,
                                  "layered animation: the mask table");
    if (!s.isOk()) return s;
    mask_table_bytes = bytes;
  }
  glNamedBufferSubData(mask_table, 0, GLsizeiptr(bytes), table.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, mask_table);
  return Status::ok();
}

void ScratchBuffers::release() {
  if (mask_table != kNoObject) glDeleteBuffers(1, &mask_table);
  mask_table = kNoObject;
  mask_table_bytes = 0;
  compute_ring.release();
  compute_previous_ring.release();
  gpu_driven_ring.release();
  gpu_driven_previous_ring.release();
  if (cpu_stream != kNoObject) glDeleteBuffers(1, &cpu_stream);
  cpu_stream = kNoObject;
  cpu_stream_bytes = 0;
}

}  // namespace si::detail
