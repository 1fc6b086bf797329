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
//
// The ring's memory is bounded whatever the crowd: an upload is staged in chunks of at most
// kChunkBytes (or the storage block limit, if smaller), so each of its kRegions regions holds at
// most twice that (RecordRing's geometric growth). One ring serves every GPU-driven crowd of a
// renderer (ScratchBuffers::uploads). Before 2026-11-28 each character's path kept its own, of
// twice its largest upload per region: 1.7 GB at 1M instances (the whole state, 144 MB).

#include <glad/gl.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gl/resources/record_ring.h"
#include "si/core/status.h"
#include "si/crowd/gpu_crowd_state.h"
#include "si/gl/gl_context.h"

namespace si::detail {

/// One piece of a buffer to write: `bytes` (a multiple of 4) of `data` at `offset` (a multiple
/// of 4).
struct BufferPiece {
  size_t offset = 0, bytes = 0;
  const void* data = nullptr;
};

/// Appends one piece per run of `runs`: elements of `element_bytes` each, dense index i at byte
/// `base` + i x element_bytes of the buffer, their data packed one run after another from
/// `packed` (what CrowdExport's ranged exports write; the stretch is staged with one copy), or
/// none (nullptr: written later, uploadWritten).
inline void appendRunPieces(const std::vector<DenseRange>& runs, size_t base, size_t element_bytes,
                            const void* packed, std::vector<BufferPiece>* pieces) {
  const uint8_t* data = static_cast<const uint8_t*>(packed);
  for (const DenseRange& r : runs) {
    const size_t bytes = size_t(r.count) * element_bytes;
    pieces->push_back({base + size_t(r.first) * element_bytes, bytes, data});
    if (data != nullptr) data += bytes;
  }
}

class UploadRing;

/// Stages `pieces` (`bytes` in all, their data ignored) into `buffer` with their bytes written
/// by `write(uint8_t* out)`, packed one piece after another: straight into the staging ring
/// when they fit one chunk (UploadRing::reserve), else into `scratch`, then staged from it.
template <class Write>
Status uploadWritten(UploadRing& ring, GLuint buffer, std::vector<BufferPiece>* pieces,
                     size_t bytes, std::vector<uint8_t>* scratch, const Write& write);

class UploadRing {
 public:
  /// Regions of the staging ring. Uploads are packed into a region one after the other (any
  /// number a frame: every view's seed, the state, the overlays); a full region is fenced and
  /// the next one is taken, so the CPU waits only for the scatters of kRegions - 1 regions
  /// back: never for the frame it is building unless that frame alone stages that much.
  static constexpr uint32_t kRegions = 6;
  /// The most one staged chunk holds (its table entries and bytes): a larger upload goes in
  /// several, the CPU waiting for the GPU's scatter of the chunk kRegions back.
  static constexpr uint64_t kChunkBytes = 4u << 20;
  /// The scatter program (ProgramId::kUploadScatter) and the context's limits; before upload().
  void prepare(GLuint scatter_program, const GlInfo& info);
  /// Where an upload staged in one chunk lies in the ring (count 0: nowhere).
  struct Staged {
    size_t base = 0;
    uint64_t staged_words = 0, words = 0;
    uint32_t count = 0, grid_x = 0, grid_y = 0;
  };
  /// Writes each piece into `buffer` after the commands already issued (and issues a storage
  /// barrier, so later passes read them), in chunks of at most kChunkBytes staged. Uses storage
  /// bindings 0 and 1. kBackend when the staging ring cannot be mapped or its region is not
  /// free within RecordRing's wait; kLimitExceeded when a chunk's scatter passes the compute
  /// grid. Chunks written before a failure stay written. The pieces' data are copied in
  /// stretches: pieces whose data follow each other in memory cost one copy.
  Status upload(GLuint buffer, const std::vector<BufferPiece>& pieces);
  Status upload(GLuint buffer, size_t bytes, const void* data) {
    return upload(buffer, std::vector<BufferPiece>{{0, bytes, data}});
  }
  /// Stages `pieces` (their data ignored) in one chunk for the caller to write: their bytes go
  /// to `*bytes`, packed one piece after another, and finish() then scatters them into
  /// `buffer`. So an export writes straight into the ring, with no copy of its own (the
  /// crowd's workers writing in parallel). nullptr in `*bytes`, with nothing staged, when they
  /// do not fit one chunk or hold an empty piece: upload() them then. No other call on the
  /// ring until finish(). kBackend and kLimitExceeded as upload().
  Status reserve(const std::vector<BufferPiece>& pieces, uint8_t** bytes, Staged* staged);
  /// Scatters what reserve() staged, its bytes written, into `buffer`.
  void finish(const Staged& staged, GLuint buffer);
  void release();
  /// The staging ring's bytes now (every region).
  size_t bytes() const { return ring_.bytes(); }

 private:
  // One chunk: each piece's 16-byte table entry, then the bytes, scattered by one dispatch.
  Status stage(GLuint buffer, const std::vector<BufferPiece>& pieces);
  // The table of a chunk written into the open region, and where its bytes go.
  Status open(const std::vector<BufferPiece>& pieces, uint8_t** bytes, Staged* out);
  // The staging ring's limit of one chunk (a multiple of 4), or kLimitExceeded.
  Status chunkLimit(uint64_t* limit) const;
  // The scatter dispatch of a staged chunk into `buffer`, between storage barriers.
  void scatter(const Staged& staged, GLuint buffer);
  RecordRing ring_;
  GLuint program_ = 0;
  uint32_t max_groups_x_ = 0, max_groups_y_ = 0;  // GlInfo's compute grid.
  uint64_t max_storage_bytes_ = 0;                // GlInfo's storage block limit.
  uint32_t alignment_ = 16;                       // Of each chunk: the storage offset alignment.
  // The region chunks are packed into (open_), from ring byte region_, cursor_ bytes used.
  size_t region_ = 0, cursor_ = 0;
  bool configured_ = false, open_ = false;
};

template <class Write>
Status uploadWritten(UploadRing& ring, GLuint buffer, std::vector<BufferPiece>* pieces,
                     size_t bytes, std::vector<uint8_t>* scratch, const Write& write) {
  uint8_t* direct = nullptr;
  UploadRing::Staged staged;
  Status s = ring.reserve(*pieces, &direct, &staged);
  if (!s.isOk()) return s;
  if (direct != nullptr) {
    write(direct);
    ring.finish(staged, buffer);
    return Status::ok();
  }
  scratch->resize(bytes);
  write(scratch->data());
  const uint8_t* data = scratch->data();
  for (BufferPiece& p : *pieces) p.data = data, data += p.bytes;
  return ring.upload(buffer, *pieces);
}

}  // namespace si::detail
