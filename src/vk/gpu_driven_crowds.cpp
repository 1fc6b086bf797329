// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's crowds: their state on the GPU, uploaded whole or in proportion to
// change.
#include "vk/gpu_driven_crowds.h"

#include <algorithm>
#include <cstring>
#include <iterator>

#include "core/str_cat.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_export.h"

namespace si::vk::detail {

using si::detail::strCat;

Status createBuffers(DeviceObjects* objects, Span<const BufferNeed> needs, VkDeviceSize max_range,
                     uint64_t instances) {
  for (const BufferNeed& need : needs)
    if (need.bytes > max_range)
      return {
          StatusCode::kLimitExceeded,
          strCat("vk::Renderer::recordGpuDrivenPasses: ", instances, " instances need ", need.bytes,
                 " bytes of ", need.what, ", past maxStorageBufferRange (", max_range, ")")};
  for (const BufferNeed& need : needs) {
    Status s = objects->createBuffer(need.bytes, need.usage, false, need.what, need.buffer);
    if (!s.isOk()) return s;
  }
  return Status::ok();
}

void GpuDrivenCrowds::init(DeviceObjects* objects, FrameRetirement* retirement,
                           VkDeviceSize max_storage_range, uint32_t frames_in_flight,
                           bool pre_skin) {
  objects_ = objects;
  retirement_ = retirement;
  max_storage_range_ = max_storage_range;
  frames_in_flight_ = frames_in_flight;
  pre_skin_ = pre_skin;
}

void GpuDrivenCrowds::retire(uint32_t slot, DrivenCrowd* d) {
  for (GpuBuffer* b : d->buffers()) retirement_->retire(slot, b);
  d->capacity = 0;
}

Status GpuDrivenCrowds::reshape(DrivenCrowd* d, uint32_t slot, uint32_t n, uint32_t sub_meshes,
                                uint32_t buckets, uint32_t clips, uint32_t times,
                                const LayerNeeds& layering) {
  retire(slot, d);
  // Room to grow by half, so a spawn wave re-creates the buffers a few times, not every frame.
  const uint64_t capacity = std::max<uint64_t>(1, uint64_t(n) + n / 2);
  const VkBufferUsageFlags storage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  const BufferNeed needs[] = {
      {&d->state, capacity * sizeof(GpuInstanceState), storage, "the crowd state"},
      {&d->clips, uint64_t(std::max(clips, 1u)) * sizeof(GpuClipInfo), storage, "the clips"},
      {&d->times, uint64_t(std::max(times, 1u)) * sizeof(double), storage, "the frame times"},
      {&d->ranges, uint64_t(buckets) * 8, storage, "the bucket ranges"},
      {&d->bucket_info, uint64_t(buckets) * 16, storage, "the bucket info"},
      {&d->identity, capacity * sub_meshes * 4, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | storage,
       "the entry indices"},
      {&d->overlays,
       layering.layers
           ? capacity * (layering.extras ? 1 + kExtraLayerRecords : 1) * sizeof(GpuOverlayState)
           : 16,
       storage, "the overlays (and 2D blends' extra layers)"},
      {&d->masks, std::max<uint64_t>(layering.mask_bytes, 16), storage, "the layer mask table"},
      {&d->compose_table, std::max<uint64_t>(layering.compose_bytes, 16), storage,
       "the compose table"}};
  Status s = createBuffers(objects_, Span<const BufferNeed>(needs, std::size(needs)),
                           max_storage_range_, n);
  if (!s.isOk()) {
    retire(slot, d);
    return s;
  }
  d->capacity = uint32_t(capacity);
  d->sub_meshes = sub_meshes;
  d->buckets = buckets;
  d->layers = layering.layers;
  d->extras = layering.extras;
  d->mask_table.clear();  // Uploaded again.
  d->compose_values.clear();
  d->shape = si::detail::ComposeShape();
  ++d->generation;
  return Status::ok();
}

Status GpuDrivenCrowds::update(VkCommandBuffer cmd, uint32_t slot, uint32_t character,
                               const CharacterResources& c, const CrowdManager& crowd,
                               DrivenCrowd** out, CrowdUpload* upload) {
  *upload = CrowdUpload();
  const CrowdDesc& cd = crowd.desc();
  const uint32_t subs = cd.sub_mesh_count, buckets = cd.lod_count * subs, n = crowd.size();
  const CrowdExport exported(crowd);
  const std::pair<uint32_t, uint64_t> key{character, crowd.identity()};
  DrivenCrowd& d = crowds_[key];
  *out = &d;
  // A new frame (motion vectors' parity): the crowd stepped (CrowdManager::stepCount(), dt 0
  // included), as si::gl's GPU-driven path counts them; passes between two steps are one frame.
  if (d.frame == 0 || crowd.stepCount() != d.frame_steps) {
    ++d.frame;
    d.frame_steps = crowd.stepCount();
  }
  // Layered animation: the overlays while some instance holds one, and the crowd's mask table
  // (masks may be added at any time: compared every frame, as si::gl uploads it every frame).
  // 2D blends: the extra layers too, and the compose table (the layers composed in a pass).
  LayerNeeds layering;
  const bool layers = layering.layers = exported.playsOverlays();
  layering.extras = layers && exported.writesExtraLayers();
  std::vector<int32_t> mask_table, compose_values;
  if (layers) mask_table = layerMaskTable(crowd.layerMasks());
  if (layering.extras) compose_values = si::detail::layerComposeTable(crowd.layerMasks());
  layering.mask_bytes = mask_table.size() * sizeof(int32_t);
  layering.compose_bytes = compose_values.size() * sizeof(int32_t);
  const bool reshaped = n > d.capacity || d.sub_meshes != subs || d.buckets != buckets ||
                        d.state.buffer == VK_NULL_HANDLE || layers != d.layers ||
                        layering.extras != d.extras || layering.mask_bytes > d.masks.size ||
                        layering.compose_bytes > d.compose_table.size ||
                        (layering.extras && si::detail::composeShape(compose_values).recordBytes() >
                                                d.shape.recordBytes());
  const bool new_masks =
      layers && (mask_table != d.mask_table || compose_values != d.compose_values);
  if (!reshaped && !new_masks && d.version == exported.stateVersion() && d.instances == n)
    return Status::ok();
  // The palette's clips and frame times: fixed for the crowd's identity (its palette is its
  // init()'s), so copied in with the buffers they size, never again.
  std::vector<GpuClipInfo> clips;
  std::vector<double> times;
  if (reshaped) {
    exported.clips(&clips, &times);
    Status s = reshape(&d, slot, n, subs, buckets, uint32_t(clips.size()), uint32_t(times.size()),
                       layering);
    if (!s.isOk()) {
      for (GpuBuffer& b : d.staging) retirement_->retire(slot, &b);
      crowds_.erase(key);
      *out = nullptr;
      return s;
    }
  }
  // What changed since the last upload (everything after a reshape): runs of dense indices, a
  // copy region each. Past half the instances the whole state is copied.
  changed_.clear();
  uint64_t changed_instances = n;
  bool whole = reshaped;
  if (!whole) {
    exported.changedSince(d.version, &changed_, nullptr);
    changed_instances = 0;
    for (const DenseRange& r : changed_) changed_instances += r.count;
    whole = changed_instances * 2 > n;
  }
  if (whole) {
    changed_.assign(n > 0 ? 1 : 0, DenseRange{0, n});
    changed_instances = n;
  }
  const VkDeviceSize state_bytes = changed_instances * sizeof(GpuInstanceState);
  const VkDeviceSize overlay_bytes = layers ? changed_instances *
                                                  (layering.extras ? 1 + kExtraLayerRecords : 1) *
                                                  sizeof(GpuOverlayState)
                                            : 0;
  const bool tables = new_masks || (layers && reshaped);
  const VkDeviceSize table_bytes = tables ? layering.mask_bytes + layering.compose_bytes : 0;
  const VkDeviceSize clip_bytes = clips.size() * sizeof(GpuClipInfo);
  const VkDeviceSize time_bytes = times.size() * sizeof(double);
  const VkDeviceSize range_bytes = reshaped ? VkDeviceSize(buckets) * 8 : 0;
  const VkDeviceSize info_bytes = reshaped ? VkDeviceSize(buckets) * 16 : 0;
  const VkDeviceSize identity_bytes = reshaped ? VkDeviceSize(d.capacity) * subs * 4 : 0;
  const VkDeviceSize total = state_bytes + overlay_bytes + table_bytes + clip_bytes + time_bytes +
                             range_bytes + info_bytes + identity_bytes;
  // This slot's staging (its last frame is done).
  if (d.staging.size() < frames_in_flight_) d.staging.resize(frames_in_flight_);
  GpuBuffer& staging = d.staging[slot];
  if (staging.size < total) {
    objects_->destroy(&staging);
    Status s =
        objects_->createBuffer(std::max<VkDeviceSize>(total, 256), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               true, "the GPU-driven state's staging", &staging);
    if (!s.isOk()) return s;
  }
  uint8_t* to = static_cast<uint8_t*>(staging.mapped);
  const Span<const DenseRange> runs(changed_.data(), changed_.size());
  // The instances first, exported straight into the staging (each byte written once), one
  // copy region per run.
  if (!changed_.empty()) exported.state(runs, reinterpret_cast<GpuInstanceState*>(to), nullptr);
  // The handle slots the views' drawn records must hold (motion vectors).
  if (whole) d.slots_needed = 1;
  for (uint64_t k = 0; k < changed_instances; ++k) {
    const uint32_t handle = reinterpret_cast<const GpuInstanceState*>(to)[k].handle;
    d.slots_needed = std::max(d.slots_needed, (handle & (HandlePool::kMaxSlots - 1)) + 1);
  }
  // One copy region per changed run, from the staging at `at` on into `buffer`: each instance's
  // `per` elements of `bytes` from element `base` on.
  std::vector<VkBufferCopy> regions;
  VkDeviceSize at = 0;
  const auto copy_runs = [&](VkBuffer buffer, VkDeviceSize bytes, VkDeviceSize base, uint32_t per) {
    regions.clear();
    for (const DenseRange& r : changed_) {
      const VkDeviceSize run_bytes = VkDeviceSize(r.count) * per * bytes;
      regions.push_back({at, (base + VkDeviceSize(r.first) * per) * bytes, run_bytes});
      at += run_bytes;
    }
    if (!regions.empty())
      vkCmdCopyBuffer(cmd, staging.buffer, buffer, uint32_t(regions.size()), regions.data());
  };
  copy_runs(d.state.buffer, sizeof(GpuInstanceState), 0, 1);
  upload->regions = uint32_t(regions.size());
  // Then their overlays, run by run as the instances.
  if (layers) {
    exported.overlays(runs, reinterpret_cast<GpuOverlayState*>(to + at));
    copy_runs(d.overlays.buffer, sizeof(GpuOverlayState), 0, 1);
  }
  // 2D blends: their extra layers, kExtraLayerRecords an instance after the overlays' capacity
  // (cull.comp.glsl's u_extras).
  if (layering.extras) {
    exported.extraLayers(runs, reinterpret_cast<GpuOverlayState*>(to + at));
    copy_runs(d.overlays.buffer, sizeof(GpuOverlayState), d.capacity, kExtraLayerRecords);
  }
  upload->state_bytes = state_bytes + overlay_bytes;
  upload->whole = whole;
  const auto copy = [&](const GpuBuffer& buffer, VkDeviceSize bytes) {
    if (bytes == 0) return;
    const VkBufferCopy region{at, 0, bytes};
    vkCmdCopyBuffer(cmd, staging.buffer, buffer.buffer, 1, &region);
    at += bytes;
  };
  if (tables) {
    std::memcpy(to + at, mask_table.data(), size_t(layering.mask_bytes));
    copy(d.masks, layering.mask_bytes);
    if (layering.compose_bytes > 0)
      std::memcpy(to + at, compose_values.data(), size_t(layering.compose_bytes));
    copy(d.compose_table, layering.compose_bytes);
    d.mask_table = std::move(mask_table);
    d.shape =
        layering.extras ? si::detail::composeShape(compose_values) : si::detail::ComposeShape();
    d.compose_values = std::move(compose_values);
  }
  if (reshaped) {
    if (clip_bytes > 0) std::memcpy(to + at, clips.data(), size_t(clip_bytes));
    copy(d.clips, clip_bytes);
    if (time_bytes > 0) std::memcpy(to + at, times.data(), size_t(time_bytes));
    copy(d.times, time_bytes);
    auto* ranges = reinterpret_cast<uint32_t*>(to + at);
    for (uint32_t b = 0; b < buckets; ++b) {
      const IndexRange r = c.lodRange(b % subs, b / subs);
      ranges[2 * b] = r.first_index;
      ranges[2 * b + 1] = r.index_count;
    }
    copy(d.ranges, range_bytes);
    auto* info = reinterpret_cast<uint32_t*>(to + at);
    for (uint32_t b = 0; b < buckets; ++b) {
      const si::detail::PreSkinLod& l = c.pre_skin.lod(b % subs, b / subs);
      info[4 * b] = pre_skin_ ? l.vertex_count : 0u;  // 0: nothing fits a ring.
      info[4 * b + 1] = l.vertex_offset;
      info[4 * b + 2] = l.first_index;
      info[4 * b + 3] = l.index_count;
    }
    copy(d.bucket_info, info_bytes);
    auto* identity = reinterpret_cast<uint32_t*>(to + at);
    for (uint32_t k = 0; k < d.capacity * subs; ++k) identity[k] = k;
    copy(d.identity, identity_bytes);
  }
  d.version = exported.stateVersion();
  d.instances = n;
  return Status::ok();
}

void GpuDrivenCrowds::evict(uint32_t slot, uint64_t before,
                            const std::vector<const DrivenCrowd*>& kept) {
  for (auto it = crowds_.begin(); it != crowds_.end();) {
    DrivenCrowd& d = it->second;
    if (d.used >= before || std::find(kept.begin(), kept.end(), &d) != kept.end()) {
      ++it;
      continue;
    }
    retire(slot, &d);
    for (GpuBuffer& b : d.staging) retirement_->retire(slot, &b);
    it = crowds_.erase(it);
  }
}

void GpuDrivenCrowds::forgetUpdatedAt(uint32_t slot, uint64_t frame,
                                      std::vector<const DrivenCrowd*>* forgotten) {
  for (auto it = crowds_.begin(); it != crowds_.end();) {
    DrivenCrowd& d = it->second;
    if (d.used != frame) {
      ++it;
      continue;
    }
    forgotten->push_back(&d);
    retire(slot, &d);
    for (GpuBuffer& b : d.staging) retirement_->retire(slot, &b);
    it = crowds_.erase(it);
  }
}

uint64_t GpuDrivenCrowds::deviceBytes() const {
  uint64_t bytes = 0;
  for (const auto& [key, d] : crowds_)
    for (const GpuBuffer* b : d.buffers()) bytes += b->size;
  return bytes;
}

void GpuDrivenCrowds::release() {
  for (auto& [key, d] : crowds_) {
    for (GpuBuffer* b : d.buffers()) objects_->destroy(b);
    for (GpuBuffer& b : d.staging) objects_->destroy(&b);
  }
  crowds_.clear();
}

}  // namespace si::vk::detail
