// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Batches sized by the uniform block limit, as in B. Dudash, "Skinned Instancing" (NVIDIA,
// 2007): 4096 float4 constants / 5 float4 per instance = 819 instances per draw.
#include "si/crowd/instance_batcher.h"

#include <cstring>

#include "core/str_cat.h"

namespace si {
using detail::strCat;

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

namespace {
size_t alignUp(size_t v, size_t a) { return (v + a - 1) / a * a; }
}  // namespace

size_t InstanceBatcher::recordBufferBound(const CrowdManager& crowd) const {
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

Status InstanceBatcher::build(const CrowdManager& crowd, Span<uint8_t> out,
                              std::vector<DrawBatch>* draws) const {
  if (capacity_ == 0) return {StatusCode::kInvalidArgument, "InstanceBatcher: init() first"};
  if (draws == nullptr) return {StatusCode::kInvalidArgument, "InstanceBatcher::build: draws is null"};
  const size_t needed = recordBufferBound(crowd);
  if (out.size() < needed)
    return {StatusCode::kCountMismatch, strCat("InstanceBatcher::build: the record buffer holds ",
                                               out.size(), " bytes, the frame needs ", needed)};
  draws->clear();
  const std::vector<uint32_t>& offsets = crowd.bucketOffsets();
  const std::vector<uint32_t>& entries = crowd.bucketEntries();
  const std::vector<InstanceRecord>& records = crowd.records();
  const uint32_t submeshes = crowd.desc().sub_mesh_count;
  size_t cursor = 0;
  for (uint32_t b = 0; b + 1 < offsets.size(); ++b) {
    for (uint32_t first = offsets[b]; first < offsets[b + 1];) {
      const uint32_t n = std::min(capacity_, offsets[b + 1] - first);
      cursor = alignUp(cursor, alignment_);
      DrawBatch d;
      d.lod = static_cast<uint16_t>(b / submeshes);
      d.sub_mesh = static_cast<uint16_t>(b % submeshes);
      d.byte_offset = static_cast<uint32_t>(cursor);
      d.instance_count = n;
      uint8_t* dst = out.data() + cursor;
      for (uint32_t k = 0; k < n; ++k)
        std::memcpy(dst + size_t(k) * kInstanceRecordSize, &records[entries[first + k]],
                    kInstanceRecordSize);
      cursor += size_t(n) * kInstanceRecordSize;
      draws->push_back(d);
      first += n;
    }
  }
  return Status::ok();
}

}  // namespace si
