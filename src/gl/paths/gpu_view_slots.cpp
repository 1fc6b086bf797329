// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's per-view slots: found by view identity, dropped when idle or too many.
#include "gl/paths/gpu_view_slots.h"

#include <algorithm>

#include "core/str_cat.h"
#include "gl/resources/gl_allocation.h"
#include "si/crowd/handle_pool.h"

namespace si::detail {

void GpuViewSlot::release() {
  const GLuint buffers[] = {instances, drawn};
  glDeleteBuffers(2, buffers);
  pyramid.release();
  instances = drawn = kNoObject;
  capacity = drawn_slots = 0;
}

Status GpuViewSlot::ensureInstances(uint32_t count) {
  if (capacity == count && instances != kNoObject) return Status::ok();
  glDeleteBuffers(1, &instances);
  instances = kNoObject;
  capacity = 0;
  seeded_upload = 0;
  const uint32_t room = std::max(count, 1u);
  Status s = createBuffer(&instances, uint64_t(room) * 8, nullptr, GL_DYNAMIC_STORAGE_BIT,
                          "GPU culling: a view's LODs and visibility flags");
  if (s.isOk()) capacity = room;
  return s;
}

Status GpuViewSlot::seed(UploadRing& uploads, const std::vector<uint32_t>& lods, uint32_t count,
                         uint64_t upload) {
  // cull.comp.glsl's SiViewInstances: handle 0 (a seed: whichever instance sits there), the
  // LOD, not visible.
  std::vector<glm::uvec2> rows(count, glm::uvec2(0u));
  for (size_t i = 0; i < rows.size() && i < lods.size(); ++i) rows[i].y = lods[i];
  const Status s = uploads.upload(instances, rows.size() * sizeof(rows[0]), rows.data());
  if (s.isOk()) seeded_upload = upload;
  return s;
}

Status GpuViewSlot::seed(UploadRing& uploads, const std::vector<uint32_t>& lods,
                         const std::vector<DenseRange>& ranges, uint64_t upload) {
  std::vector<glm::uvec2> rows(lods.size());
  for (size_t k = 0; k < lods.size(); ++k) rows[k] = glm::uvec2(0u, lods[k]);  // As above.
  std::vector<BufferPiece> pieces;
  pieces.reserve(ranges.size());
  size_t at = 0;
  for (const DenseRange& r : ranges) {
    if (r.first + r.count > capacity) break;  // Never past the buffer (the caller sized it).
    pieces.push_back({size_t(r.first) * sizeof(rows[0]), size_t(r.count) * sizeof(rows[0]),
                      rows.data() + at});
    at += r.count;
  }
  const Status s = uploads.upload(instances, pieces);
  if (s.isOk()) seeded_upload = upload;
  return s;
}

Status GpuViewSlot::ensureDrawn(uint32_t slots_needed, uint64_t max_block_bytes) {
  if (slots_needed <= drawn_slots) return Status::ok();
  const uint32_t slots = drawnSlotsToMake(slots_needed, drawn_slots, max_block_bytes);
  const uint64_t bytes = uint64_t(slots) * 2 * kDrawnBytes;
  if (bytes > max_block_bytes)
    return {StatusCode::kLimitExceeded,
            strCat("drawCrowdGpuCulled: motion vectors keep ", bytes, " bytes of drawn records for ",
                   slots, " handle slots, GL_MAX_SHADER_STORAGE_BLOCK_SIZE is ", max_block_bytes)};
  glDeleteBuffers(1, &drawn);
  drawn = kNoObject;
  drawn_slots = 0;
  Status s = createBuffer(&drawn, bytes, nullptr, GL_DYNAMIC_STORAGE_BIT,
                          "motion vectors: a view's drawn records");
  if (!s.isOk()) return s;
  // No tag names a handle (handle ids are never 0): every instance starts with the fallback.
  glClearNamedBufferData(drawn, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  drawn_slots = slots;
  return Status::ok();
}

GpuViewSlot* GpuViewSlots::find(uint64_t view, uint32_t frame) {
  for (const std::unique_ptr<GpuViewSlot>& s : slots_)
    if (s->view == view) return s.get();
  // Idle views go first, then the least recently drawn while the slots are full.
  const auto idle = [frame](const std::unique_ptr<GpuViewSlot>& s) {
    return frame - s->last_frame > kIdleFrames;
  };
  for (std::unique_ptr<GpuViewSlot>& s : slots_)
    if (idle(s)) s->release();
  slots_.erase(std::remove_if(slots_.begin(), slots_.end(), idle), slots_.end());
  if (slots_.size() >= kMaxViews) {
    auto oldest = std::min_element(slots_.begin(), slots_.end(),
                                   [](const std::unique_ptr<GpuViewSlot>& a,
                                      const std::unique_ptr<GpuViewSlot>& b) {
                                     return a->last_frame < b->last_frame;
                                   });
    (*oldest)->release();
    slots_.erase(oldest);
  }
  slots_.push_back(std::make_unique<GpuViewSlot>());
  GpuViewSlot* s = slots_.back().get();
  s->view = view;
  s->last_frame = frame;
  return s;
}

void GpuViewSlots::clear() {
  for (std::unique_ptr<GpuViewSlot>& s : slots_) s->release();
  slots_.clear();
}

uint64_t GpuViewSlots::gpuBytes() const {
  uint64_t total = 0;
  for (const std::unique_ptr<GpuViewSlot>& s : slots_)
    total += bufferBytes(s->instances) + bufferBytes(s->drawn) + s->pyramid.gpuBytes();
  return total;
}

}  // namespace si::detail
