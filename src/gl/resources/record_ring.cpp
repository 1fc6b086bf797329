// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The fenced, persistently mapped instance-record ring.
#include "gl/resources/record_ring.h"

#include <algorithm>

#include "core/str_cat.h"
#include "gl/profile/gl_profile.h"
#include "gl/resources/gl_allocation.h"
#include "si/gl/gl_context.h"

namespace si::detail {

void RecordRing::configure(uint32_t block_size, uint32_t alignment, uint32_t frames,
                           uint32_t storage_alignment) {
  block_size_ = block_size;
  alignment_ = alignment;
  region_alignment_ = std::max(alignment, storage_alignment);  // Both powers of two.
  frames_ = frames;
}

void RecordRing::setRegions(uint32_t regions) {
  if (regions == frames_) return;
  waitAll();
  release();
  frames_ = regions;
}

void RecordRing::waitAll() {
  for (GLsync& f : fences_)
    if (f) {
      glClientWaitSync(f, GL_SYNC_FLUSH_COMMANDS_BIT, kWaitNanoseconds);
      glDeleteSync(f);
      f = nullptr;
    }
}

Status RecordRing::reserve(size_t bytes_per_frame) {
  const size_t need = (bytes_per_frame + alignment_ - 1) / alignment_ * alignment_ + block_size_;
  if (buffer_ != kNoObject && need <= region_size_) return Status::ok();
  waitAll();
  deleteBuffers();
  first_valid_ = serial_;  // The regions written so far are gone with the buffer.
  region_size_ = std::max<size_t>(need * 2, size_t(1) << 20);  // Grow geometrically.
  region_size_ = (region_size_ + region_alignment_ - 1) / region_alignment_ * region_alignment_;
  const size_t ring_size = region_size_ * frames_;
  buffer_ = kNoObject;
  mapped_ = nullptr;
  es_ = esProfile();
  if (es_) {  // No fences either: each upload goes to storage no queued draw reads.
    fences_.assign(frames_, nullptr);
    es_buffers_.assign(frames_, kNoObject);
    Status s = Status::ok();
    for (GLuint& b : es_buffers_)
      if (s.isOk())
        s = createMutableBuffer(&b, region_size_, GL_DYNAMIC_DRAW, "the instance record ring");
    if (!s.isOk()) {
      deleteBuffers();
      region_size_ = 0;
      return s;
    }
    shadow_.assign(ring_size, 0);
    mapped_ = shadow_.data();
    return Status::ok();
  }
  const GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  Status s = createBuffer(&buffer_, ring_size, nullptr, flags, "the instance record ring");
  fences_.assign(frames_, nullptr);
  if (!s.isOk()) {
    region_size_ = 0;
    return s;
  }
  mapped_ = static_cast<uint8_t*>(glMapNamedBufferRange(buffer_, 0, GLsizeiptr(ring_size), flags));
  if (mapped_ == nullptr) {
    glDeleteBuffers(1, &buffer_);
    buffer_ = kNoObject;
    region_size_ = 0;
    return {StatusCode::kBackend,
            "mapping the instance record ring failed (out of memory or past the buffer limit)"};
  }
  return Status::ok();
}

Status RecordRing::acquire(size_t* base) {
  GLsync& f = fences_[index_];
  if (f) {
    const GLenum waited = (wait_ != nullptr ? wait_ : glClientWaitSync)(
        f, GL_SYNC_FLUSH_COMMANDS_BIT, kWaitNanoseconds);
    if (waited == GL_WAIT_FAILED)
      return {StatusCode::kBackend,
              strCat("the instance record ring: waiting for the GPU failed (",
                     glErrorName(glGetError()), ")")};
    if (waited != GL_ALREADY_SIGNALED && waited != GL_CONDITION_SATISFIED)
      return {StatusCode::kBackend,
              strCat("the instance record ring: the GPU has not finished reading its region ",
                     "after ", kWaitNanoseconds / 1000000000u, " s (lost or overloaded device)")};
    glDeleteSync(f);
    f = nullptr;
  }
  *base = size_t(index_) * region_size_;
  return Status::ok();
}

void RecordRing::publish(size_t base, size_t bytes) const {
  if (!es_ || bytes == 0) return;
  size_t at = 0;
  const GLuint buffer = bufferAt(base, &at);
  // Orphaned: fresh storage of the same size (the driver keeps the old while draws read it).
  glNamedBufferData(buffer, GLsizeiptr(region_size_), nullptr, GL_DYNAMIC_DRAW);
  glNamedBufferSubData(buffer, GLintptr(at), GLsizeiptr(bytes), mapped_ + base);
}

void RecordRing::deleteBuffers() {
  if (buffer_ != kNoObject) {
    if (!es_) glUnmapNamedBuffer(buffer_);
    glDeleteBuffers(1, &buffer_);
  }
  buffer_ = kNoObject;
  if (!es_buffers_.empty()) glDeleteBuffers(GLsizei(es_buffers_.size()), es_buffers_.data());
  es_buffers_.clear();
}

void RecordRing::finishFrame() {
  if (!es_) {
    fences_[index_] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    if (has_borrowed_ && holds(borrowed_)) {
      GLsync& f = fences_[(index_ + frames_ - (serial_ - borrowed_)) % frames_];
      if (f) glDeleteSync(f);
      f = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    }
  }
  has_borrowed_ = false;
  index_ = (index_ + 1) % frames_;
  ++serial_;
}

void RecordRing::release() {
  for (GLsync f : fences_)
    if (f) glDeleteSync(f);
  fences_.clear();
  deleteBuffers();
  mapped_ = nullptr;
  shadow_.clear();
  shadow_.shrink_to_fit();
  region_size_ = 0;
  index_ = 0;
  first_valid_ = serial_;
  has_borrowed_ = false;
}

}  // namespace si::detail
