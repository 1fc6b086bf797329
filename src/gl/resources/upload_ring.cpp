// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Staged uploads: a table and the pieces through a fenced staging ring, scattered into place by
// one compute dispatch (upload_ring.h).
#include "gl/resources/upload_ring.h"

#include <algorithm>
#include <cstring>

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
    alignment_ = std::max<uint32_t>(16, info.storage_buffer_offset_alignment);
    configured_ = true;
  }
}

Status UploadRing::chunkLimit(uint64_t* limit) const {
  // The scatter binds a chunk whole: within the storage block limit too. At least one table
  // entry and one word.
  *limit = std::min<uint64_t>(kChunkBytes, max_storage_bytes_) / 4 * 4;
  if (*limit < 20)
    return {StatusCode::kLimitExceeded,
            strCat("staged upload: GL_MAX_SHADER_STORAGE_BLOCK_SIZE (", max_storage_bytes_,
                   ") holds no table entry and word")};
  return Status::ok();
}

namespace {

// Whether `pieces` fit one chunk of `limit` bytes as given (tables and bytes) with no piece
// empty.
bool oneChunk(const std::vector<BufferPiece>& pieces, uint64_t limit) {
  uint64_t all = 0;
  for (const BufferPiece& p : pieces) {
    if (p.bytes == 0) return false;
    all += 16 + p.bytes;
  }
  return all <= limit;
}

}  // namespace

Status UploadRing::upload(GLuint buffer, const std::vector<BufferPiece>& pieces) {
  uint64_t limit = 0;
  Status s = chunkLimit(&limit);
  if (!s.isOk()) return s;
  // In one chunk as given when it fits and no piece is empty (the loop below drops those).
  if (oneChunk(pieces, limit)) return pieces.empty() ? Status::ok() : stage(buffer, pieces);
  std::vector<BufferPiece> chunk;
  uint64_t staged = 0;
  for (BufferPiece p : pieces) {
    while (p.bytes > 0) {
      if (staged + 20 > limit) {  // No room for another entry and word: stage this chunk.
        s = stage(buffer, chunk);
        if (!s.isOk()) return s;
        chunk.clear();
        staged = 0;
      }
      const size_t take = size_t(std::min<uint64_t>(p.bytes, limit - staged - 16));
      chunk.push_back({p.offset, take, p.data});
      staged += 16 + take;
      p.offset += take;
      p.bytes -= take;
      p.data = static_cast<const uint8_t*>(p.data) + take;
    }
  }
  return chunk.empty() ? Status::ok() : stage(buffer, chunk);
}

void UploadRing::scatter(const Staged& staged, GLuint buffer) {
  // Earlier passes' reads and writes of `buffer` before the scatter's writes.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(program_);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, ring_.buffer(), GLintptr(staged.base),
                    GLsizeiptr(staged.staged_words * 4));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffer);
  glProgramUniform1ui(program_, 0, staged.count);
  glProgramUniform1ui(program_, 1, uint32_t(staged.words));
  glDispatchCompute(staged.grid_x, staged.grid_y, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // The passes after read what it wrote.
}

Status UploadRing::reserve(const std::vector<BufferPiece>& pieces, uint8_t** bytes,
                           Staged* staged) {
  *bytes = nullptr;
  *staged = Staged{};
  uint64_t limit = 0;
  Status s = chunkLimit(&limit);
  if (!s.isOk() || pieces.empty() || !oneChunk(pieces, limit)) return s;
  return open(pieces, bytes, staged);
}

void UploadRing::finish(const Staged& staged, GLuint buffer) {
  ring_.publish(staged.base, size_t(staged.staged_words) * 4);
  scatter(staged, buffer);
}

Status UploadRing::open(const std::vector<BufferPiece>& pieces, uint8_t** bytes, Staged* out) {
  uint64_t words = 0;
  const uint32_t count = uint32_t(pieces.size());
  for (const BufferPiece& p : pieces) words += p.bytes / 4;
  const uint64_t staged_words = uint64_t(count) * 4 + words;
  DispatchGrid grid;
  if (!dispatchGrid((words + 63) / 64, max_groups_x_, max_groups_y_, &grid))
    return {StatusCode::kLimitExceeded,
            strCat("staged upload: ", words, " words exceed the compute grid")};
  // Packed into the open region after the uploads before it; a new region when it is full.
  const size_t need = (size_t(staged_words) * 4 + alignment_ - 1) / alignment_ * alignment_;
  if (open_ && cursor_ + need > ring_.writableBytes()) {
    ring_.finishFrame();  // Fenced after every scatter that reads it.
    open_ = false;
  }
  if (!open_) {
    Status s = ring_.reserve(need);
    if (s.isOk()) s = ring_.acquire(&region_);
    if (!s.isOk()) return s;
    cursor_ = 0;
    open_ = true;
  }
  const size_t base = region_ + cursor_;
  cursor_ += need;
  // The table, then the bytes: two sequential streams into the write-combined mapping (one
  // stream alternating between the two wrote partial lines: slow for many small pieces).
  uint32_t* staged = reinterpret_cast<uint32_t*>(ring_.mapped(base));
  uint32_t at = count * 4, k = 0;
  for (const BufferPiece& p : pieces) {
    const uint32_t n = uint32_t(p.bytes / 4);
    const uint32_t entry[4] = {at, uint32_t(p.offset / 4), n, at - count * 4};
    std::memcpy(staged + 4 * k++, entry, sizeof entry);
    at += n;
  }
  *bytes = reinterpret_cast<uint8_t*>(staged + count * 4);
  *out = Staged{base, staged_words, words, count, grid.x, grid.y};
  return Status::ok();
}

Status UploadRing::stage(GLuint buffer, const std::vector<BufferPiece>& pieces) {
  uint8_t* bytes = nullptr;
  Staged chunk;
  Status s = open(pieces, &bytes, &chunk);
  if (!s.isOk()) return s;
  // The bytes: one copy for each stretch of pieces whose data follow each other in memory
  // (a packed export's runs: one copy in all).
  for (size_t p = 0; p < pieces.size();) {
    const uint8_t* from = static_cast<const uint8_t*>(pieces[p].data);
    size_t n = pieces[p].bytes;
    for (++p; p < pieces.size() && pieces[p].data == from + n; ++p) n += pieces[p].bytes;
    std::memcpy(bytes, from, n);
    bytes += n;
  }
  finish(chunk, buffer);
  return Status::ok();
}

void UploadRing::release() {
  ring_.release();
  configured_ = open_ = false;
}

}  // namespace si::detail
