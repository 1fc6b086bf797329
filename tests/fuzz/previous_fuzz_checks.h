// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd API fuzzer's checks of an update's motion-vector data (crowd_api_fuzz.cpp): the
// previous records and indices, the batcher's previous blocks, and where build() puts each
// record (the table drawCrowd reads the last frame's records through).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

namespace si::fuzz {

// Motion vectors: each record's previous index is none or names a kept record; the batcher's
// previous block (build()'s layout) holds finite world rows; each slot's previous index
// (buildPreviousIndices, directly and through a table) is none or names a kept record.
inline void checkPreviousRecords(const CrowdManager& crowd, const InstanceBatcher& batcher,
                                 void (*fail)(const char*)) {
  if (!crowd.desc().previous_records) return;
  if (crowd.view().previousRecordIndices().size() != crowd.view().records().size())
    fail("the previous indices do not match the records");
  for (uint32_t p : crowd.view().previousRecordIndices())
    if (p != kNoPreviousRecord && p >= crowd.view().previousRecords().size())
      fail("a previous index is past the previous records");
  std::vector<uint8_t> now(batcher.recordBufferBound(crowd.view())), then(now.size());
  std::vector<DrawBatch> draws;
  if (!batcher.build(crowd.view(), now, &draws).isOk() ||
      !batcher.buildPrevious(crowd.view(), then).isOk())
    fail("build or buildPrevious failed on a valid frame");
  // drawCrowd's form: each slot's index, none or a kept previous record.
  std::vector<uint8_t> indices(batcher.previousIndexBufferBound(crowd.view()));
  if (!batcher.buildPreviousIndices(crowd.view(), indices).isOk())
    fail("buildPreviousIndices failed on a valid frame");
  for (const DrawBatch& d : draws)
    for (uint32_t k = 0; k < d.instance_count; ++k) {
      InstanceRecord r;
      std::memcpy(&r, then.data() + d.byte_offset + k * kInstanceRecordSize, sizeof r);
      for (const auto& row : r.world_rows)
        for (float v : row)
          if (!std::isfinite(v)) fail("a previous record's world rows are not finite");
      uint32_t p;
      std::memcpy(&p, indices.data() + (d.layer_byte_offset / kLayerRecordSize + k) * 4, 4);
      if (p != kNoPreviousRecord && p >= crowd.view().previousRecords().size())
        fail("a slot's previous index is past the previous records");
    }
  // Through a table (drawCrowd reading the last frame's region): each index looked up.
  std::vector<uint32_t> table(crowd.view().previousRecords().size());
  for (size_t p = 0; p < table.size(); ++p) table[p] = uint32_t(p * 5 + 3);
  std::vector<uint8_t> looked_up(indices.size());
  if (!batcher.buildPreviousIndices(crowd.view(), looked_up, table).isOk())
    fail("buildPreviousIndices through a table failed on a valid frame");
  for (const DrawBatch& d : draws)
    for (uint32_t k = 0; k < d.instance_count; ++k) {
      const size_t at = (d.layer_byte_offset / kLayerRecordSize + k) * 4;
      uint32_t p, q;
      std::memcpy(&p, indices.data() + at, 4);
      std::memcpy(&q, looked_up.data() + at, 4);
      if (q != (p < table.size() ? table[p] : kNoPreviousRecord))
        fail("a slot's index through the table is not the table's entry");
    }
}

// Where build() put each record (buildRecordPlaces): none, or a copy of it.
inline void checkRecordPlaces(const CrowdManager& crowd, const InstanceBatcher& batcher,
                              void (*fail)(const char*)) {
  std::vector<uint8_t> now(batcher.recordBufferBound(crowd.view()));
  std::vector<DrawBatch> draws;
  std::vector<uint32_t> places(crowd.view().records().size());
  if (!batcher.build(crowd.view(), now, &draws).isOk() ||
      !batcher.buildRecordPlaces(crowd.view(), places).isOk())
    fail("build or buildRecordPlaces failed on a valid frame");
  for (size_t i = 0; i < places.size(); ++i) {
    if (places[i] == InstanceBatcher::kNoRecordPlace) continue;
    if (size_t(places[i]) * 16 + kInstanceRecordSize > now.size())
      fail("a record's place is past build()'s buffer");
    else if (std::memcmp(now.data() + size_t(places[i]) * 16, &crowd.view().records()[i],
                         kInstanceRecordSize) != 0)
      fail("a record's place does not hold the record");
  }
}

// Each slot's instance handle (buildHandles): a live instance's, drawn this frame, whose record
// is the slot's.
inline void checkSlotHandles(const CrowdManager& crowd, const InstanceBatcher& batcher,
                             void (*fail)(const char*)) {
  std::vector<uint8_t> now(batcher.recordBufferBound(crowd.view())),
      handles(batcher.handleBufferBound(crowd.view()));
  std::vector<DrawBatch> draws;
  if (!batcher.build(crowd.view(), now, &draws).isOk() ||
      !batcher.buildHandles(crowd.view(), handles).isOk())
    fail("build or buildHandles failed on a valid frame");
  const Span<const InstanceHandle> visible = crowd.view().visibleHandles();
  for (const DrawBatch& d : draws)
    for (uint32_t k = 0; k < d.instance_count; ++k) {
      InstanceHandle h;
      std::memcpy(&h.id, handles.data() + (d.layer_byte_offset / kLayerRecordSize + k) * 4, 4);
      if (!crowd.contains(h)) fail("a slot's handle is not a live instance's");
      const InstanceHandle* at = std::find(visible.begin(), visible.end(), h);
      if (at == visible.end()) {
        fail("a slot's handle was not drawn this frame");
        continue;
      }
      if (std::memcmp(now.data() + d.byte_offset + k * kInstanceRecordSize,
                      &crowd.view().records()[size_t(at - visible.begin())],
                      kInstanceRecordSize) != 0)
        fail("a slot's handle is not its record's instance's");
    }
}

}  // namespace si::fuzz
