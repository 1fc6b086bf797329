// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The draw paths' shared scratch buffers.
#include "gl/resources/scratch_buffers.h"

#include "gl/resources/gl_allocation.h"

namespace si::detail {

Status VertexRing::ensure(uint64_t wanted, bool exact, const char* what) {
  if (buffer != kNoObject && (exact ? vertices == wanted : vertices >= wanted))
    return Status::ok();
  vertices = 0;
  Status s = createBuffer(&buffer, wanted * vertex_bytes, nullptr, 0, what);
  if (s.isOk()) vertices = wanted;
  return s;
}

void VertexRing::release() {
  if (buffer != kNoObject) glDeleteBuffers(1, &buffer);
  buffer = kNoObject;
  vertices = 0;
}

Status ScratchBuffers::uploadMaskTable(const std::vector<int32_t>& table) {
  return mask_table.upload(table, 8, "layered animation: the mask table");
}

void ScratchBuffers::release() {
  mask_table.release();
  layer_compose.release();
  uploads.release();
  compute_ring.release();
  compute_previous_ring.release();
  gpu_driven_ring.release();
  gpu_driven_previous_ring.release();
  compute_tangent_ring.release();
  gpu_driven_tangent_ring.release();
  if (cpu_stream != kNoObject) glDeleteBuffers(1, &cpu_stream);
  cpu_stream = kNoObject;
  cpu_stream_bytes = 0;
}

}  // namespace si::detail
