// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Recent draws' records in the ring, read again as the next frame's previous records.
#include "gl/resources/drawn_regions.h"

#include <algorithm>

#include "core/str_cat.h"

namespace si::detail {

const DrawnRegion* DrawnRegions::find(uint64_t view, uint64_t selection,
                                      const RecordRing& ring) const {
  for (const DrawnRegion& r : regions_)
    if (r.view == view && r.selection == selection && r.complete && ring.canBorrow(r.serial))
      return &r;
  return nullptr;
}

Status DrawnRegions::keep(const InstanceBatcher& batcher, const CrowdView& view,
                          const RecordRing& ring, size_t records, size_t records_end) {
  DrawnRegion* slot = nullptr;
  for (DrawnRegion& r : regions_)
    if (r.view == view.identity() && r.selection == view.selectionCount()) slot = &r;
  for (DrawnRegion& r : regions_)
    if (slot == nullptr && !ring.holds(r.serial)) slot = &r;
  if (slot == nullptr && regions_.size() < kKept) slot = &regions_.emplace_back();
  if (slot == nullptr)
    slot = &*std::min_element(
        regions_.begin(), regions_.end(),
        [](const DrawnRegion& a, const DrawnRegion& b) { return a.serial < b.serial; });
  slot->view = view.identity();
  slot->selection = view.selectionCount();
  slot->serial = ring.serial();
  slot->records = records;
  slot->records_end = records_end;
  const size_t count = view.records().size();
  if (slot->places.size() < count) slot->places.resize(count);
  const Status s = batcher.buildRecordPlaces(view, slot->places);
  slot->complete =
      s.isOk() && std::find(slot->places.begin(), slot->places.begin() + count,
                            InstanceBatcher::kNoRecordPlace) == slot->places.begin() + count;
  return s;
}

Status reserveRingFrame(const InstanceBatcher& batcher, const CrowdView& view, uint32_t alignment,
                        const RingContents& contents, uint64_t storage_limit,
                        const DrawnRegions& regions, RecordRing* ring, RingFrame* plan,
                        const DrawnRegion** previous) {
  *previous =
      contents.motion ? regions.find(view.identity(), view.selectionCount() - 1, *ring) : nullptr;
  *plan = planRingFrame(batcher, view, alignment, contents, *previous == nullptr);
  if (*previous != nullptr) {
    const Status s = ring->reserve(plan->end);
    if (!s.isOk()) return s;
    // Growing re-creates the buffer; a ring past one binding cannot bind both regions.
    if (!ring->canBorrow((*previous)->serial) || ring->bytes() > storage_limit) {
      *previous = nullptr;
      *plan = planRingFrame(batcher, view, alignment, contents, true);
    }
  }
  if (contents.motion && plan->previous_end - plan->previous_indices > storage_limit)
    return {StatusCode::kLimitExceeded,
            strCat("drawCrowd: motion vectors: the frame's previous-record indices and records (",
                   plan->previous_end - plan->previous_indices,
                   " bytes) exceed GL_MAX_SHADER_STORAGE_BLOCK_SIZE (", storage_limit, ")")};
  if (contents.handles && plan->handles_end - plan->handle_words > storage_limit)
    return {
        StatusCode::kLimitExceeded,
        strCat("drawCrowd: the frame's instance handles (", plan->handles_end - plan->handle_words,
               " bytes, MaterialDesc::instance_handle) exceed GL_MAX_SHADER_STORAGE_BLOCK_SIZE (",
               storage_limit, ")")};
  return ring->reserve(plan->end);
}

PreviousBinding previousBinding(const RingFrame& plan, size_t base, const DrawnRegion* previous) {
  PreviousBinding b;
  const size_t indices = base + plan.previous_indices;
  const size_t records = previous != nullptr ? previous->records : base + plan.previous_records;
  const size_t end =
      std::max(base + plan.previous_end, previous != nullptr ? previous->records_end : size_t(0));
  b.base = std::min(indices, records);
  b.bytes = end - b.base;
  b.words = glm::uvec3((indices - b.base) / 16, (records - b.base) / 16,
                       previous != nullptr ? 1u : kInstanceRecordSize / 16);
  return b;
}

}  // namespace si::detail
