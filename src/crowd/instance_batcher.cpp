// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Batches sized by the uniform block limit, as in B. Dudash, "Skinned Instancing" (NVIDIA,
// 2007): 4096 float4 constants / 5 float4 per instance = 819 instances per draw.
#include "si/crowd/instance_batcher.h"

#include <algorithm>
#include <cstring>
#include <numeric>

#include "core/str_cat.h"
#include "crowd/batch_walk.h"

namespace si {
using detail::alignUp;
using detail::strCat;
using detail::walkBatches;

Status InstanceBatcher::init(const BatchLimits& limits) {
  const uint32_t alignment =
      limits.uniform_buffer_offset_alignment == 0 ? 256u : limits.uniform_buffer_offset_alignment;
  if (limits.max_uniform_block_size_bytes < 16384)
    return {StatusCode::kInvalidArgument,
            strCat("BatchLimits.max_uniform_block_size_bytes ", limits.max_uniform_block_size_bytes,
                   " is below GL's minimum of 16384")};
  if ((alignment & (alignment - 1)) != 0 || alignment > 65536)
    return {StatusCode::kInvalidArgument,
            "BatchLimits.uniform_buffer_offset_alignment must be a power of two <= 65536"};
  const uint32_t fit = limits.max_uniform_block_size_bytes / kInstanceRecordSize;
  if (limits.max_instances_per_draw > fit)
    return {StatusCode::kInvalidArgument,
            strCat("BatchLimits.max_instances_per_draw ", limits.max_instances_per_draw,
                   " exceeds the ", fit, " records the block holds")};
  capacity_ = limits.max_instances_per_draw == 0 ? fit : limits.max_instances_per_draw;
  alignment_ = alignment;
  return Status::ok();
}

size_t InstanceBatcher::recordBufferBound(const CrowdView& crowd) const {
  if (capacity_ == 0) return 0;
  const std::vector<uint32_t>& offsets = crowd.bucketOffsets();
  size_t bytes = 0;
  for (uint32_t b = 0; b + 1 < offsets.size(); ++b) {
    uint32_t left = offsets[b + 1] - offsets[b];
    while (left > 0) {
      const uint32_t n = left < capacity_ ? left : capacity_;
      bytes = alignUp(bytes, alignment_) + size_t(n) * kInstanceRecordSize;
      left -= n;
    }
  }
  return bytes;
}

namespace {

// Writes each slot's 32-bit word, its record's entry of `words` (one per record), at
// (layer_byte_offset / 16 + slot) * 4 of `out`: buildLayers()' slot numbering.
void writeSlotWords(const CrowdView& crowd, uint32_t capacity, uint32_t alignment,
                    const uint32_t* words, uint8_t* out) {
  walkBatches(crowd, capacity, alignment, nullptr,
              [&](const DrawBatch& d, uint32_t slot, uint32_t first, uint32_t count) {
                std::memcpy(out + (d.layer_byte_offset / kLayerRecordSize + slot) * 4,
                            words + first, size_t(count) * sizeof(uint32_t));
              });
}

// Writes each slot's `per_slot` previous layer records at (layer_byte_offset / 16 + slot) *
// per_slot * 16 of `out`: its instance's records in `previous` (per_slot per previous record)
// through previousRecordIndices(); where it has no previous record, its current ones
// (`current`); where the previous update wrote none, zero records.
void writePreviousLayers(const CrowdView& crowd, uint32_t capacity, uint32_t alignment,
                         Span<const LayerRecord> current, Span<const LayerRecord> previous,
                         uint32_t per_slot, uint8_t* out) {
  const size_t previous_records = crowd.previousRecords().size();
  const Span<const uint32_t> index = crowd.previousRecordIndices();
  const size_t slot_bytes = size_t(per_slot) * kLayerRecordSize;
  const std::vector<LayerRecord> zero(per_slot);
  walkBatches(crowd, capacity, alignment, nullptr,
              [&](const DrawBatch& d, uint32_t slot, uint32_t first, uint32_t count) {
                uint8_t* dst = out + (d.layer_byte_offset / kLayerRecordSize + slot) * slot_bytes;
                for (uint32_t k = 0; k < count; ++k) {
                  const uint32_t i = first + k, p = index[i];
                  const LayerRecord* rec = p >= previous_records
                                               ? current.data() + size_t(i) * per_slot
                                           : (size_t(p) + 1) * per_slot <= previous.size()
                                               ? previous.data() + size_t(p) * per_slot
                                               : zero.data();
                  std::memcpy(dst + size_t(k) * slot_bytes, rec, slot_bytes);
                }
              });
}

}  // namespace

Status InstanceBatcher::build(const CrowdView& crowd, Span<uint8_t> out,
                              std::vector<DrawBatch>* draws) const {
  if (capacity_ == 0) return {StatusCode::kInvalidArgument, "InstanceBatcher: init() first"};
  if (draws == nullptr)
    return {StatusCode::kInvalidArgument, "InstanceBatcher::build: draws is null"};
  const size_t needed = recordBufferBound(crowd);
  if (out.size() < needed)
    return {StatusCode::kCountMismatch, strCat("InstanceBatcher::build: the record buffer holds ",
                                               out.size(), " bytes, the frame needs ", needed)};
  draws->clear();
  const uint8_t* records = reinterpret_cast<const uint8_t*>(crowd.records().data());
  uint8_t* dst = out.data();
  walkBatches(crowd, capacity_, alignment_, draws,
              [&](const DrawBatch& d, uint32_t slot, uint32_t first, uint32_t count) {
                std::memcpy(dst + d.byte_offset + size_t(slot) * kInstanceRecordSize,
                            records + size_t(first) * kInstanceRecordSize,
                            size_t(count) * kInstanceRecordSize);
              });
  return Status::ok();
}

glm::vec3 previousRecordShift(const CrowdView& view) {
  return previousRecordShift(view.camera().position, view.previousCamera().position);
}

glm::vec3 previousRecordShift(const glm::dvec3& now, const glm::dvec3& then) {
  // A camera cut too far for a float (past 1e30) keeps the translation (no motion is
  // meaningful there).
  const glm::dvec3 delta = now - then;
  const bool representable = glm::all(glm::lessThan(glm::abs(delta), glm::dvec3(1e30)));
  return representable ? glm::vec3(delta) : glm::vec3(0.0f);
}

Status InstanceBatcher::checkPreviousBuffer(const char* what, const char* buffer,
                                            const CrowdView& crowd, size_t out_bytes,
                                            size_t needed) const {
  if (capacity_ == 0) return {StatusCode::kInvalidArgument, "InstanceBatcher: init() first"};
  if (!crowd.desc().previous_records)
    return {StatusCode::kInvalidArgument,
            strCat("InstanceBatcher::", what, ": the crowd keeps no previous records ",
                   "(CrowdDesc::previous_records, CrowdViewDesc::previous_records)")};
  if (out_bytes < needed)
    return {StatusCode::kCountMismatch,
            strCat("InstanceBatcher::", what, ": the ", buffer, " buffer holds ", out_bytes,
                   " bytes, the frame needs ", needed)};
  return Status::ok();
}

Status InstanceBatcher::buildPrevious(const CrowdView& crowd, Span<uint8_t> out) const {
  const Status s =
      checkPreviousBuffer("buildPrevious", "record", crowd, out.size(), recordBufferBound(crowd));
  if (!s.isOk()) return s;
  const Span<const InstanceRecord> records = crowd.records();
  const Span<const InstanceRecord> previous = crowd.previousRecords();
  const Span<const uint32_t> index = crowd.previousRecordIndices();
  const glm::vec3 shift = previousRecordShift(crowd);
  uint8_t* base = out.data();
  walkBatches(crowd, capacity_, alignment_, nullptr,
              [&](const DrawBatch& d, uint32_t slot, uint32_t first, uint32_t count) {
                uint8_t* dst = base + d.byte_offset + size_t(slot) * kInstanceRecordSize;
                for (uint32_t k = 0; k < count; ++k) {
                  const uint32_t i = first + k, p = index[i];
                  InstanceRecord rec = p < previous.size() ? previous[p] : records[i];
                  if (p >= previous.size())
                    for (int row = 0; row < 3; ++row) rec.world_rows[row][3] += shift[row];
                  std::memcpy(dst + size_t(k) * kInstanceRecordSize, &rec, kInstanceRecordSize);
                }
              });
  return Status::ok();
}

size_t InstanceBatcher::previousIndexBufferBound(const CrowdView& crowd) const {
  return layerBufferBound(crowd) / kLayerRecordSize * sizeof(uint32_t);
}

Status InstanceBatcher::buildPreviousIndices(const CrowdView& crowd, Span<uint8_t> out) const {
  const Status s = checkPreviousBuffer("buildPreviousIndices", "index", crowd, out.size(),
                                       previousIndexBufferBound(crowd));
  if (!s.isOk()) return s;
  writeSlotWords(crowd, capacity_, alignment_, crowd.previousRecordIndices().data(), out.data());
  return Status::ok();
}

Status InstanceBatcher::buildPreviousIndices(const CrowdView& crowd, Span<uint8_t> out,
                                             Span<const uint32_t> previous_places) const {
  Status s = checkPreviousBuffer("buildPreviousIndices", "index", crowd, out.size(),
                                 previousIndexBufferBound(crowd));
  const size_t previous = crowd.previousRecords().size();
  if (s.isOk() && previous_places.size() < previous)
    s = {StatusCode::kCountMismatch,
         strCat("InstanceBatcher::buildPreviousIndices: the place table holds ",
                previous_places.size(), " entries, the previous selection drew ", previous,
                " records")};
  if (!s.isOk()) return s;
  const Span<const uint32_t> index = crowd.previousRecordIndices();
  uint8_t* base = out.data();
  walkBatches(crowd, capacity_, alignment_, nullptr,
              [&](const DrawBatch& d, uint32_t slot, uint32_t first, uint32_t count) {
                uint32_t* dst = reinterpret_cast<uint32_t*>(base) +
                                d.layer_byte_offset / kLayerRecordSize + slot;
                for (uint32_t k = 0; k < count; ++k) {
                  const uint32_t p = index[first + k];
                  dst[k] = p < previous ? previous_places[p] : kNoPreviousRecord;
                }
              });
  return Status::ok();
}

size_t InstanceBatcher::handleBufferBound(const CrowdView& crowd) const {
  return layerBufferBound(crowd) / kLayerRecordSize * sizeof(uint32_t);
}

Status InstanceBatcher::buildHandles(const CrowdView& crowd, Span<uint8_t> out) const {
  if (capacity_ == 0) return {StatusCode::kInvalidArgument, "InstanceBatcher: init() first"};
  const size_t bound = handleBufferBound(crowd);
  if (out.size() < bound)
    return {StatusCode::kCountMismatch,
            strCat("InstanceBatcher::buildHandles: the buffer holds ", out.size(),
                   " bytes, the frame's handles need ", bound)};
  static_assert(sizeof(InstanceHandle) == sizeof(uint32_t), "a handle is its 32-bit id");
  writeSlotWords(crowd, capacity_, alignment_,
                 reinterpret_cast<const uint32_t*>(crowd.visibleHandles().data()), out.data());
  return Status::ok();
}

Status InstanceBatcher::buildRecordPlaces(const CrowdView& crowd, Span<uint32_t> out) const {
  if (capacity_ == 0) return {StatusCode::kInvalidArgument, "InstanceBatcher: init() first"};
  const size_t records = crowd.records().size();
  if (out.size() < records)
    return {StatusCode::kCountMismatch,
            strCat("InstanceBatcher::buildRecordPlaces: the place table holds ", out.size(),
                   " entries, the frame has ", records, " records")};
  std::fill(out.data(), out.data() + records, kNoRecordPlace);
  walkBatches(crowd, capacity_, alignment_, nullptr,
              [&](const DrawBatch& d, uint32_t slot, uint32_t first, uint32_t count) {
                const uint32_t word = (d.byte_offset + slot * kInstanceRecordSize) / 16;
                for (uint32_t k = 0; k < count; ++k)
                  out[first + k] = word + k * (kInstanceRecordSize / 16);
              });
  return Status::ok();
}

size_t InstanceBatcher::layerBufferBound(const CrowdView& crowd) const {
  if (capacity_ == 0) return 0;
  const std::vector<uint32_t>& offsets = crowd.bucketOffsets();
  size_t bytes = 0;
  for (uint32_t b = 0; b + 1 < offsets.size(); ++b)
    for (uint32_t left = offsets[b + 1] - offsets[b]; left > 0;) {
      const uint32_t n = left < capacity_ ? left : capacity_;
      bytes = alignUp(bytes, alignment_) + size_t(n) * kLayerRecordSize;
      left -= n;
    }
  return bytes;
}

Status InstanceBatcher::checkLayerBuffer(const char* what, const CrowdView& crowd, size_t out_bytes,
                                         bool extra, bool previous) const {
  if (capacity_ == 0) return {StatusCode::kInvalidArgument, "InstanceBatcher: init() first"};
  if (previous && !crowd.desc().previous_records)
    return {StatusCode::kInvalidArgument,
            strCat("InstanceBatcher::", what, ": the crowd keeps no previous records ",
                   "(CrowdDesc::previous_records, CrowdViewDesc::previous_records)")};
  if ((extra ? crowd.extraLayerRecords() : crowd.layerRecords()).empty())
    return {StatusCode::kInvalidArgument,
            strCat("InstanceBatcher::", what, ": the crowd's last update wrote no ",
                   extra ? "extra layer records (no 2D blend space)"
                         : "layer records (no instance plays an overlay)")};
  const size_t needed = extra ? extraLayerBufferBound(crowd) : layerBufferBound(crowd);
  if (out_bytes < needed)
    return {StatusCode::kCountMismatch,
            strCat("InstanceBatcher::", what, ": the ", extra ? "extra " : "",
                   "layer buffer holds ", out_bytes, " bytes, the frame needs ", needed)};
  return Status::ok();
}

Status InstanceBatcher::buildLayers(const CrowdView& crowd, Span<uint8_t> out) const {
  const Status s = checkLayerBuffer("buildLayers", crowd, out.size(), false, false);
  if (!s.isOk()) return s;
  const Span<const LayerRecord> layers = crowd.layerRecords();
  uint8_t* base = out.data();
  walkBatches(crowd, capacity_, alignment_, nullptr,
              [&](const DrawBatch& d, uint32_t slot, uint32_t first, uint32_t count) {
                std::memcpy(base + d.layer_byte_offset + size_t(slot) * kLayerRecordSize,
                            layers.data() + first, size_t(count) * kLayerRecordSize);
              });
  return Status::ok();
}

Status InstanceBatcher::buildPreviousLayers(const CrowdView& crowd, Span<uint8_t> out) const {
  const Status s = checkLayerBuffer("buildPreviousLayers", crowd, out.size(), false, true);
  if (!s.isOk()) return s;
  writePreviousLayers(crowd, capacity_, alignment_, crowd.layerRecords(),
                      crowd.previousLayerRecords(), 1, out.data());
  return Status::ok();
}

size_t InstanceBatcher::extraLayerBufferBound(const CrowdView& crowd) const {
  return layerBufferBound(crowd) * kExtraLayerRecords;
}

Status InstanceBatcher::buildExtraLayers(const CrowdView& crowd, Span<uint8_t> out) const {
  const Status s = checkLayerBuffer("buildExtraLayers", crowd, out.size(), true, false);
  if (!s.isOk()) return s;
  const Span<const LayerRecord> extras = crowd.extraLayerRecords();
  constexpr size_t kSlotBytes = kExtraLayerRecords * kLayerRecordSize;
  uint8_t* base = out.data();
  walkBatches(crowd, capacity_, alignment_, nullptr,
              [&](const DrawBatch& d, uint32_t slot, uint32_t first, uint32_t count) {
                std::memcpy(base + (d.layer_byte_offset / kLayerRecordSize + slot) * kSlotBytes,
                            extras.data() + size_t(first) * kExtraLayerRecords,
                            size_t(count) * kSlotBytes);
              });
  return Status::ok();
}

Status InstanceBatcher::buildPreviousExtraLayers(const CrowdView& crowd, Span<uint8_t> out) const {
  const Status s = checkLayerBuffer("buildPreviousExtraLayers", crowd, out.size(), true, true);
  if (!s.isOk()) return s;
  writePreviousLayers(crowd, capacity_, alignment_, crowd.extraLayerRecords(),
                      crowd.previousExtraLayerRecords(), kExtraLayerRecords, out.data());
  return Status::ok();
}

Status InstanceBatcher::buildSpans(const CrowdView& crowd,
                                   std::vector<RecordSpanDraw>* draws) const {
  if (capacity_ == 0) return {StatusCode::kInvalidArgument, "InstanceBatcher: init() first"};
  if (draws == nullptr)
    return {StatusCode::kInvalidArgument, "InstanceBatcher::buildSpans: draws is null"};
  draws->clear();
  // Records per aligned block start: alignment / gcd(80, alignment).
  const uint32_t step = alignment_ / std::gcd(kInstanceRecordSize, alignment_);
  const std::vector<uint32_t>& run_offsets = crowd.bucketRunOffsets();
  const std::vector<RecordRun>& runs = crowd.bucketRuns();
  const uint32_t submeshes = crowd.subMeshCount();
  for (uint32_t b = 0; b + 1 < run_offsets.size(); ++b) {
    for (uint32_t r = run_offsets[b]; r < run_offsets[b + 1]; ++r) {
      for (uint32_t first = runs[r].first, left = runs[r].count; left > 0;) {
        const uint32_t block = first / step * step;
        if (first - block >= capacity_)
          return {StatusCode::kUnsupported,
                  strCat("InstanceBatcher::buildSpans: an alignment of ", alignment_,
                         " bytes puts block starts up to ", step - 1, " records before a draw, ",
                         "more than the ", capacity_, " a block holds; use build()")};
        const uint32_t n = std::min(left, capacity_ - (first - block));
        RecordSpanDraw d;
        d.lod = static_cast<uint16_t>(b / submeshes);
        d.sub_mesh = static_cast<uint16_t>(b % submeshes);
        d.first_record = first;
        d.instance_count = n;
        d.block_first_record = block;
        draws->push_back(d);
        first += n;
        left -= n;
      }
    }
  }
  return Status::ok();
}

}  // namespace si
