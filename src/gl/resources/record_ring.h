// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The instance-record ring: one persistently mapped buffer of `frames` regions, each guarded by
// a fence, so the CPU writes a frame's records while the GPU still reads earlier frames'. On the
// ES profile (no persistent mapping, no fences) the records are written to a copy in memory and
// publish() uploads each frame's bytes into a buffer of the region's own (the regions rotate
// through `frames` buffers), orphaned first (glBufferData with no data): an upload never writes
// storage a queued draw still reads, so a tile-based GPU neither stalls nor copies for it.

#include <glad/gl.h>

#include <cstdint>
#include <vector>

#include "gl/programs/program_set.h"
#include "si/crowd/instance_batcher.h"

namespace si::detail {

/// glClientWaitSync's signature: the ring waits through one (tests hand it others).
using ClientWaitSync = GLenum(GLAD_API_PTR*)(GLsync sync, GLbitfield flags, GLuint64 timeout);

class RecordRing {
 public:
  /// How long acquire() waits for the GPU to finish reading a region before it gives up.
  static constexpr GLuint64 kWaitNanoseconds = GLuint64(1e10);
  /// The uniform block size every bound range has, the offset alignment and the region count;
  /// regions start at multiples of `storage_alignment` too (bindRegion).
  void configure(uint32_t block_size, uint32_t alignment, uint32_t frames,
                 uint32_t storage_alignment = 0);
  /// Changes the region count (one region per draw call group); waits for the GPU and drops
  /// the buffer, which the next reserve() re-creates.
  void setRegions(uint32_t regions);
  /// Makes each region hold at least `bytes_per_frame` (plus a block of slack, so a range of
  /// the full block size bound at the last batch stays inside the buffer). Regrows
  /// geometrically, waiting for the GPU first. kBackend when mapping fails.
  Status reserve(size_t bytes_per_frame);
  /// Waits until the GPU is done with the current region and gives its byte offset in `base`.
  /// kBackend when the wait fails (GL_WAIT_FAILED, naming the GL error) or the GPU has not
  /// finished reading the region within kWaitNanoseconds: nothing may be written then, and the
  /// region's fence stays for the next try.
  Status acquire(size_t* base);
  /// Makes the `bytes` written at `base` visible to the GPU: nothing to do with the persistent
  /// coherent mapping; an upload on the ES profile. Call after writing, before drawing.
  void publish(size_t base, size_t bytes) const;
  /// The buffer holding the region at ring byte `base`, and `base`'s offset in it: the one
  /// buffer on desktop GL; the region's own buffer on the ES profile.
  GLuint bufferAt(size_t base, size_t* offset) const {
    if (!es_ || region_size_ == 0) {
      *offset = base;
      return buffer_;
    }
    const size_t region = base / region_size_;
    *offset = base - region * region_size_;
    return region < es_buffers_.size() ? es_buffers_[region] : kNoObject;
  }
  /// Fences the current region (and one borrow()ed this frame) and moves to the next.
  void finishFrame();
  /// The current region's serial: regions finished so far (each finishFrame() moves it on).
  uint64_t serial() const { return serial_; }
  /// Whether the region finished as `serial` still holds what was written there while the
  /// current region is written: not the current one, not reached again, the buffer not
  /// re-created since.
  bool holds(uint64_t serial) const {
    return serial >= first_valid_ && serial < serial_ && serial_ - serial < frames_;
  }
  /// Whether the current draw may read the region of `serial` (borrow()): the ring holds it,
  /// and when the ring comes round to it, at least one draw will lie between the current one
  /// and the draw acquiring it, so that acquire() never waits for the draw just before it.
  bool canBorrow(uint64_t serial) const { return holds(serial) && serial_ - serial + 2 <= frames_; }
  /// The current frame reads the region of `serial` (canBorrow()): finishFrame fences it
  /// again, so it is not written before the GPU is done with this frame too.
  void borrow(uint64_t serial) {
    borrowed_ = serial;
    has_borrowed_ = true;
  }
  void release();

  /// The mapped bytes of the region at `base` that records may be written to.
  uint8_t* mapped(size_t base) const { return mapped_ + base; }
  size_t writableBytes() const { return region_size_ - block_size_; }
  /// Binds batch `d` of the records at `base` to uniform buffer binding `binding` (0: the
  /// records; 1: the previous records of motion vectors) with `block_size` bytes.
  void bindBatch(size_t base, const DrawBatch& d, GLuint binding = 0) const {
    size_t at = 0;
    const GLuint buffer = bufferAt(base, &at);
    glBindBufferRange(GL_UNIFORM_BUFFER, binding, buffer, GLintptr(at + d.byte_offset),
                      GLsizeiptr(block_size_));
  }
  /// Binds batch `d`'s layer records of the layer block at `base` to uniform binding 2 (the
  /// block's records at 16 bytes each).
  void bindLayers(size_t base, const DrawBatch& d, GLuint binding = 2) const {
    size_t at = 0;
    const GLuint buffer = bufferAt(base, &at);
    glBindBufferRange(GL_UNIFORM_BUFFER, binding, buffer, GLintptr(at + d.layer_byte_offset),
                      GLsizeiptr(block_size_ / kInstanceRecordSize * kLayerRecordSize));
  }
  /// Binds `bytes` of the ring at `base` (a multiple of the storage alignment configure()
  /// was given) to shader storage binding `binding`, for the passes that read it by 16-byte
  /// word; at least 16 bytes (GL refuses an empty range; the region's slack holds them).
  void bindRegion(size_t base, size_t bytes, GLuint binding) const {
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, binding, buffer_, GLintptr(base),
                      GLsizeiptr(bytes < 16 ? 16 : bytes));
  }
  GLuint buffer() const { return buffer_; }
  /// The whole ring's bytes (every region).
  size_t bytes() const { return region_size_ * frames_; }
  /// The wait acquire() uses; null restores glClientWaitSync. For tests of the timeout and
  /// failure paths.
  void setClientWait(ClientWaitSync wait) { wait_ = wait; }

 private:
  void waitAll();

  GLuint buffer_ = kNoObject;
  uint8_t* mapped_ = nullptr;
  bool es_ = false;  // The ES profile: mapped_ is shadow_'s bytes.
  std::vector<uint8_t> shadow_;
  std::vector<GLuint> es_buffers_;  // The ES profile: each region's buffer (buffer_ unused).
  void deleteBuffers();             // buffer_ (unmapped first) and es_buffers_.
  size_t region_size_ = 0;
  uint32_t block_size_ = 0, alignment_ = 256, region_alignment_ = 256, frames_ = 3, index_ = 0;
  // Regions finished so far; the first whose bytes are still there (the buffer was re-created
  // before it); the one borrow() named, if has_borrowed_.
  uint64_t serial_ = 0, first_valid_ = 0, borrowed_ = 0;
  bool has_borrowed_ = false;
  std::vector<GLsync> fences_;
  ClientWaitSync wait_ = nullptr;
};

}  // namespace si::detail
