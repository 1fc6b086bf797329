// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A batched draw's frame in the record ring.
#include "crowd/ring_frame.h"

#include <cstring>

namespace si::detail {

RingFrame planRingFrame(const InstanceBatcher& batcher, const CrowdView& view, uint32_t alignment,
                        const RingContents& contents, bool copy_previous) {
  const auto align = [&](size_t v) { return (v + alignment - 1) / alignment * alignment; };
  const bool motion = contents.motion, layers = contents.layers;
  RingFrame f;
  f.motion = motion;
  f.layers = layers;
  const size_t record_bound = batcher.recordBufferBound(view);
  f.records_end = record_bound;
  size_t end = record_bound;
  if (motion) {
    f.previous_copied = copy_previous;
    f.previous_indices = align(end);
    f.previous_end = f.previous_indices + batcher.previousIndexBufferBound(view);
    if (copy_previous) {
      f.previous_records = align(f.previous_end);
      f.previous_end = f.previous_records + view.previousRecords().size() * kInstanceRecordSize;
    }
    end = f.previous_end;
  }
  if (layers) {
    const size_t layer_bound = batcher.layerBufferBound(view);
    f.layer_slots = layer_bound / kLayerRecordSize;
    f.layer_records = align(end);
    end = f.layer_records + layer_bound;
    if (motion) {
      f.previous_layers = align(end);
      end = f.previous_layers + layer_bound;
    }
    f.extras = !view.extraLayerRecords().empty();
    if (f.extras) {
      const size_t extra_bound = batcher.extraLayerBufferBound(view);
      f.extra_layers = align(end);
      end = f.extra_layers + extra_bound;
      if (motion) {
        f.previous_extras = align(end);
        end = f.previous_extras + extra_bound;
      }
    }
    f.compose_entries = align(end);
    f.compose_slots = align(f.compose_entries + view.records().size() * 8);
    end = f.compose_slots + layer_bound / kLayerRecordSize * 4;
  }
  f.handles = contents.handles;
  if (f.handles) {
    f.handle_words = align(end);
    f.handles_end = f.handle_words + batcher.handleBufferBound(view);
    end = f.handles_end;
  }
  f.end = end;
  return f;
}

Status writeRingFrame(const InstanceBatcher& batcher, const CrowdView& view, const RingFrame& f,
                      uint8_t* region, size_t bytes, Span<const uint32_t> previous_places,
                      std::vector<DrawBatch>* batches) {
  const auto at = [&](size_t offset) { return Span<uint8_t>(region + offset, bytes - offset); };
  Status s = batcher.build(view, at(0), batches);
  if (s.isOk() && f.motion && !f.previous_copied)
    s = batcher.buildPreviousIndices(view, at(f.previous_indices), previous_places);
  if (s.isOk() && f.motion && f.previous_copied) {
    s = batcher.buildPreviousIndices(view, at(f.previous_indices));
    const Span<const InstanceRecord> previous = view.previousRecords();
    if (s.isOk() && !previous.empty())
      std::memcpy(region + f.previous_records, previous.data(),
                  previous.size() * kInstanceRecordSize);
  }
  if (s.isOk() && f.layers) s = batcher.buildLayers(view, at(f.layer_records));
  if (s.isOk() && f.layers && f.motion)
    s = batcher.buildPreviousLayers(view, at(f.previous_layers));
  if (s.isOk() && f.extras) s = batcher.buildExtraLayers(view, at(f.extra_layers));
  if (s.isOk() && f.extras && f.motion)
    s = batcher.buildPreviousExtraLayers(view, at(f.previous_extras));
  if (s.isOk() && f.handles) s = batcher.buildHandles(view, at(f.handle_words));
  return s;
}

}  // namespace si::detail
