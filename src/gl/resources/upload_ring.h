// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Uploads into buffers that passes already issued may still be reading (the GPU-driven path's
// instance state, overlays and view seeds, rewritten in part every frame): the pieces go into a
// fenced, persistently mapped staging ring (RecordRing) with a table of where each belongs, and
// one compute dispatch (shaders/upload_scatter.comp.glsl) copies them into place after those
// passes. glNamedBufferSubData alone should be ordered so; on the H100's driver passes issued
// (and flushed) before it read the new bytes, a blend's new weight in the previous frame's motion
// vectors (Blend2dRenderTest.MotionAndDepthFollowTheBlend), with immutable and mutable buffers
// alike. A GPU copy per piece was ordered too but cost 3 ms a frame for 1000 scattered
// instances; a staging buffer created per upload, 14 ms at 100k instances.

#include <glad/gl.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gl/resources/record_ring.h"
#include "si/core/status.h"
#include "si/gl/gl_context.h"

namespace si::detail {

/// One piece of a buffer to write: `bytes` (a multiple of 4) of `data` at `offset` (a multiple
/// of 4).
struct BufferPiece {
  size_t offset = 0, bytes = 0;
  const void* data = nullptr;
};

class UploadRing {
 public:
  /// Regions of the staging ring: an upload waits for the GPU to finish the scatter issued this
  /// many uploads before (about two frames of the GPU-driven path's uploads).
  static constexpr uint32_t kRegions = 6;
  /// The scatter program (ProgramId::kUploadScatter) and the context's limits; before upload().
  void prepare(GLuint scatter_program, const GlInfo& info);
  /// Writes each piece into `buffer` after the commands already issued (and issues a storage
  /// barrier, so later passes read them). Uses storage bindings 0 and 1. kBackend when the
  /// staging ring cannot be mapped or its region is not free within RecordRing's wait;
  /// kLimitExceeded past 2^32 words, the compute grid or, staged with its table, the storage
  /// block limit (GL_MAX_SHADER_STORAGE_BLOCK_SIZE).
  Status upload(GLuint buffer, const std::vector<BufferPiece>& pieces);
  Status upload(GLuint buffer, size_t bytes, const void* data) {
    return upload(buffer, std::vector<BufferPiece>{{0, bytes, data}});
  }
  void release();
  /// What upload() stages for `pieces` non-empty pieces of `bytes` in all: each piece's 16-byte
  /// table entry, then the bytes (the staged region the scatter binds whole).
  static uint64_t stagedBytes(uint32_t pieces, uint64_t bytes) {
    return uint64_t(pieces) * 16 + bytes;
  }

 private:
  RecordRing ring_;
  GLuint program_ = 0;
  uint32_t max_groups_x_ = 0, max_groups_y_ = 0;  // GlInfo's compute grid.
  uint64_t max_storage_bytes_ = 0;                // GlInfo's storage block limit.
  bool configured_ = false;
};

}  // namespace si::detail
