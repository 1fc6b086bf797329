// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Staged uploads: a table and the pieces through a fenced staging ring, scattered into place by
// one compute dispatch (upload_ring.h).
#include "gl/resources/upload_ring.h"

#include <cstring>
#include <limits>

#include "core/str_cat.h"
#include "gl/paths/dispatch_grid.h"

namespace si::detail {

void UploadRing::prepare(GLuint scatter_program, const GlInfo& info) {
  program_ = scatter_program;
  max_groups_x_ = info.max_compute_groups_x;
  max_groups_y_ = info.max_compute_groups_y;
  max_storage_bytes_ = info.max_shader_storage_block_size_bytes;
  if (!configured_) {
    ring_.configure(16, 16, kRegions, info.storage_buffer_offset_alignment);
    configured_ = true;
  }
}

Status UploadRing::upload(GLuint buffer, const std::vector<BufferPiece>& pieces) {
  uint64_t words = 0;
  uint32_t count = 0;
  for (const BufferPiece& p : pieces)
    if (p.bytes > 0) {
      words += p.bytes / 4;
      ++count;
    }
  if (count == 0) return Status::ok();
  const uint64_t staged_words = stagedBytes(count, words * 4) / 4;
  DispatchGrid grid;
  if (staged_words > std::numeric_limits<uint32_t>::max() ||
      !dispatchGrid((words + 63) / 64, max_groups_x_, max_groups_y_, &grid))
    return {StatusCode::kLimitExceeded,
            strCat("staged upload: ", words, " words exceed 2^32 or the compute grid")};
  if (staged_words * 4 > max_storage_bytes_)  // The scatter binds the staged region whole.
    return {StatusCode::kLimitExceeded,
            strCat("staged upload: ", staged_words * 4,
                   " bytes, past GL_MAX_SHADER_STORAGE_BLOCK_SIZE (", max_storage_bytes_, ")")};
  Status s = ring_.reserve(size_t(staged_words) * 4);
  size_t base = 0;
  if (s.isOk()) s = ring_.acquire(&base);
  if (!s.isOk()) return s;
  uint32_t* staged = reinterpret_cast<uint32_t*>(ring_.mapped(base));
  uint32_t at = count * 4, thread = 0, k = 0;
  for (const BufferPiece& p : pieces) {
    if (p.bytes == 0) continue;
    const uint32_t n = uint32_t(p.bytes / 4);
    const uint32_t entry[4] = {at, uint32_t(p.offset / 4), n, thread};
    std::memcpy(staged + 4 * k++, entry, sizeof entry);
    std::memcpy(staged + at, p.data, size_t(n) * 4);
    at += n;
    thread += n;
  }
  ring_.publish(base, size_t(staged_words) * 4);
  // Earlier passes' reads and writes of `buffer` before the scatter's writes.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(program_);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, ring_.buffer(), GLintptr(base),
                    GLsizeiptr(staged_words * 4));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffer);
  glProgramUniform1ui(program_, 0, count);
  glProgramUniform1ui(program_, 1, uint32_t(words));
  glDispatchCompute(grid.x, grid.y, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // The passes after read what it wrote.
  ring_.finishFrame();
  return Status::ok();
}

void UploadRing::release() {
  ring_.release();
  configured_ = false;
}

}  // namespace si::detail
