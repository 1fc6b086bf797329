// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's uploads: the whole crowd state, its buffers (re)created, when the
// crowd's layout or address changes (uploadState); then in proportion to change: only the
// instances the crowd changed since the last upload (CrowdExport::changedSince) are exported
// and written, and only where other instances sit now do the views start their history over.
// And the overlays, whole. Every write goes through the staging ring (resources/upload_ring.h):
// the last frame's passes may still be reading these buffers. Each view's LODs and flags are
// seeded after an upload.
#include <algorithm>

#include "core/str_cat.h"
#include "gl/paths/gpu_culled_layout.h"
#include "gl/paths/gpu_culled_path.h"
#include "gl/resources/gl_allocation.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/handle_pool.h"

namespace si::detail {

namespace {

// One storage buffer the GPU-driven passes bind whole, and its bytes.
struct StorageNeed {
  const char* what;
  uint64_t bytes;
};

// kLimitExceeded naming the first of `needs` past GL_MAX_SHADER_STORAGE_BLOCK_SIZE, for a crowd
// of `n` instances; ok when each fits.
template <size_t N>
Status storageFits(const GlInfo& info, uint32_t n, const StorageNeed (&needs)[N]) {
  const uint64_t limit = info.max_shader_storage_block_size_bytes;
  for (const StorageNeed& need : needs)
    if (need.bytes > limit)
      return {StatusCode::kLimitExceeded,
              strCat("drawCrowdGpuCulled: ", n, " instances need ", need.bytes, " bytes of ",
                     need.what, ", past GL_MAX_SHADER_STORAGE_BLOCK_SIZE (", limit, ")")};
  return Status::ok();
}

}  // namespace

Status GpuCulledPath::uploadState(const DrawResources& r, const CrowdManager& crowd,
                                  uint32_t buckets) {
  const CrowdExport exported(crowd);
  const CrowdDesc& cd = crowd.desc();
  const uint32_t n = crowd.size();
  std::vector<GpuInstanceState> state;
  std::vector<InstanceHandle> handles;
  exported.state(&state, &handles);
  // Motion vectors key what was drawn by handle slot: as many as the largest slot.
  slots_needed_ = 1;
  for (const InstanceHandle& h : handles)
    slots_needed_ = std::max(slots_needed_, (h.id & (HandlePool::kMaxSlots - 1)) + 1);
  std::vector<GpuClipInfo> clips;
  std::vector<double> times;
  exported.clips(&clips, &times);
  const uint32_t entries = std::max(1u, n) * cd.sub_mesh_count;
  // Every buffer the passes bind whole (the overlays: uploadOverlays; a view's: ensureDrawn).
  const uint64_t slots = std::max(n, 1u);
  const StorageNeed needs[] = {
      {"crowd state", slots * sizeof(GpuInstanceState)},
      {"records", slots * kInstanceRecordSize},
      {"visible list", slots * 16},
      {"bucket entries", uint64_t(entries) * 4},
      {"entry data", uint64_t(entries) * 8},
      {"clips", uint64_t(clips.size()) * sizeof(GpuClipInfo)},
      {"frame times", uint64_t(times.size()) * sizeof(double)},
      {"impostor quads", cd.impostor_lod != 0 ? slots * kImpostorQuadBytes : 0}};
  Status s = storageFits(*r.info, n, needs);
  if (!s.isOk()) return s;
  const bool shrink = shrinks(n);
  const bool impostors = cd.impostor_lod != 0;
  if (n > capacity_ || shrink || sub_meshes_ != cd.sub_mesh_count || records_ == kNoObject ||
      impostors != (impostor_quads_ != kNoObject)) {
    // Room to grow (half as much again, of the buffers when outgrown, of the crowd when shrunk
    // after a peak), so that a spawn wave re-creates the buffers and uploads the whole state a
    // few times, not every frame: within the handle slots and the storage-block limit (the
    // state's 144 bytes an instance, or the entry data's 8 per sub-mesh, whichever is more).
    const uint64_t fit = r.info->max_shader_storage_block_size_bytes /
                         std::max<uint64_t>(sizeof(GpuInstanceState), 8 * cd.sub_mesh_count);
    const uint64_t from = shrink ? n : capacity_;
    const uint64_t grown = std::min<uint64_t>({from + from / 2, HandlePool::kMaxSlots, fit});
    const uint32_t capacity = uint32_t(std::max<uint64_t>({n, 1u, grown}));
    capacity_ = 0;  // Until every buffer below exists.
    const uint32_t entry_capacity = capacity * cd.sub_mesh_count;
    std::vector<uint32_t> identity(entry_capacity);
    for (uint32_t k = 0; k < entry_capacity; ++k) identity[k] = k;
    s = recreate(&state_, size_t(capacity) * sizeof(GpuInstanceState), nullptr,
                 "GPU culling: the crowd state");
    if (s.isOk())
      s = recreate(&records_, size_t(capacity) * kInstanceRecordSize, nullptr,
                   "GPU culling: the records");
    if (s.isOk())
      s = recreate(&visible_, size_t(capacity) * 16, nullptr, "GPU culling: the visible list");
    if (s.isOk())
      s = recreate(&entries_, size_t(entry_capacity) * 4, nullptr,
                   "GPU culling: the bucket entries");
    if (s.isOk())
      s = recreate(&identity_, identity.size() * 4, identity.data(),
                   "GPU culling: the entry indices");
    if (s.isOk())
      s = recreate(&entry_data_, size_t(entry_capacity) * 8, nullptr,
                   "GPU culling: the entry data");
    glDeleteBuffers(1, &impostor_quads_);
    impostor_quads_ = kNoObject;
    if (s.isOk() && impostors)
      s = recreate(&impostor_quads_, size_t(capacity) * kImpostorQuadBytes, nullptr,
                   "GPU culling: the impostor quads");
    if (!s.isOk()) return s;
    capacity_ = capacity;
    sub_meshes_ = cd.sub_mesh_count;
  }
  if (n > 0) {
    Status up = staging_->upload(state_, state.size() * sizeof(state[0]), state.data());
    if (!up.isOk()) return up;
  }
  uploaded_bytes_ += state.size() * sizeof(state[0]);
  s = uploadOverlays(*r.info, crowd);
  if (!s.isOk()) return s;
  std::vector<glm::uvec2> ranges(buckets);
  std::vector<glm::uvec4> info(buckets);
  for (uint32_t b = 0; b < buckets; ++b) {
    const uint32_t sm = b % cd.sub_mesh_count, lod = b / cd.sub_mesh_count;
    const IndexRange range = r.character->lodRange(sm, lod);
    ranges[b] = glm::uvec2(range.first_index, range.index_count);
    const PreSkinLists::Lod& l = r.preskin->lod(sm, lod);
    info[b] = glm::uvec4(l.vertex_count, l.vertex_offset, l.first_index, l.index_count);
  }
  s = recreate(&clips_, clips.size() * sizeof(GpuClipInfo), clips.data(), "GPU culling: the clips");
  if (s.isOk())
    s = recreate(&times_, times.size() * sizeof(double), times.empty() ? nullptr : times.data(),
                 "GPU culling: the frame times");
  if (s.isOk() && counters_ == kNoObject)
    s = recreate(&counters_, size_t(kCounterWords) * 4, nullptr, "GPU culling: the counters");
  if (s.isOk() && counts_read_back_ == kNoObject)
    s = recreate(&counts_read_back_, size_t(kCounterWords) * 4 * 2, nullptr,
                 "GPU culling: the counters read back");
  if (s.isOk() && commands_ == kNoObject)
    s = recreate(&commands_, size_t(kImpostorCommand) + 16, nullptr, "GPU culling: the commands");
  if (s.isOk()) s = recreate(&ranges_, ranges.size() * 8, ranges.data(), "GPU culling: the ranges");
  if (s.isOk())
    s = recreate(&bucket_info_, info.size() * 16, info.data(), "GPU culling: the bucket lists");
  if (!s.isOk()) {
    crowd_ = nullptr;  // Uploaded again next frame.
    return s;
  }
  if (vao_ != kNoObject) glDeleteVertexArrays(1, &vao_);
  glCreateVertexArrays(1, &vao_);
  r.character->describeVertexFormat(vao_);
  glVertexArrayVertexBuffer(vao_, 1, identity_, 0, 4);
  glVertexArrayBindingDivisor(vao_, 1, 1);
  glEnableVertexArrayAttrib(vao_, 5);
  glVertexArrayAttribBinding(vao_, 5, 1);
  glVertexArrayAttribIFormat(vao_, 5, 1, GL_UNSIGNED_INT, 0);
  // Pre-skinned draws: the re-indexed triangles, and the same entry index.
  if (preskin_vao_ != kNoObject) glDeleteVertexArrays(1, &preskin_vao_);
  glCreateVertexArrays(1, &preskin_vao_);
  glVertexArrayElementBuffer(preskin_vao_, r.preskin->index_buffer);
  glVertexArrayVertexBuffer(preskin_vao_, 1, identity_, 0, 4);
  glVertexArrayBindingDivisor(preskin_vao_, 1, 1);
  glEnableVertexArrayAttrib(preskin_vao_, 5);
  glVertexArrayAttribBinding(preskin_vao_, 5, 1);
  glVertexArrayAttribIFormat(preskin_vao_, 5, 1, GL_UNSIGNED_INT, 0);
  crowd_ = &crowd;
  uploaded_identity_ = crowd.identity();
  ++uploads_;  // Every view's LODs and flags are seeded again (indices may name others now).
  placed_upload_ = 0;
  version_ = exported.stateVersion();
  instances_ = n;
  buckets_ = buckets;
  vertex_source_ = r.character->vertex_buffer;
  return Status::ok();
}

Status GpuCulledPath::uploadOverlays(const GlInfo& info, const CrowdManager& crowd) {
  const CrowdExport exported(crowd);
  std::vector<GpuOverlayState> overlays, extras;
  exported.overlays(&overlays);
  layers_ = !overlays.empty();
  extras_ = layers_ && exported.writesExtraLayers();
  if (!layers_) return Status::ok();
  Status s = Status::ok();
  const uint32_t copies = extras_ ? 1 + kExtraLayerRecords : 1;
  // As many as the state holds (capacity_, set by uploadState first), so they grow and shrink
  // together, where the storage-block limit has room (else the crowd's own count, refused below
  // past the limit).
  const uint64_t fit = info.max_shader_storage_block_size_bytes /
                       (copies * std::max<uint64_t>(sizeof(GpuOverlayState), kLayerRecordSize));
  const uint64_t layered = std::max<uint64_t>(std::min<uint64_t>(capacity_, fit), overlays.size());
  const StorageNeed needs[] = {
      {"overlays (and 2D blends' extra layers)", layered * copies * sizeof(GpuOverlayState)},
      {"layer records", layered * copies * kLayerRecordSize}};
  s = storageFits(info, uint32_t(layered), needs);
  if (!s.isOk()) return s;
  if (layered != layer_capacity_ || overlays_ == kNoObject || copies > layer_copies_) {
    layer_capacity_ = 0;
    const size_t capacity = size_t(layered) * copies;
    s = createBuffer(&overlays_, capacity * sizeof(GpuOverlayState), nullptr,
                     GL_DYNAMIC_STORAGE_BIT, "GPU culling: the overlays");
    if (s.isOk())
      s = createBuffer(&layers_out_, capacity * kLayerRecordSize, nullptr,
                       GL_DYNAMIC_STORAGE_BIT, "GPU culling: the layer records");
    if (!s.isOk()) return s;
    layer_capacity_ = uint32_t(layered);
    layer_copies_ = copies;
  }
  std::vector<BufferPiece> pieces{{0, overlays.size() * sizeof(GpuOverlayState), overlays.data()}};
  if (extras_) {  // After the overlays' capacity (cull.comp.glsl's u_extras).
    exported.extraLayers(&extras);
    pieces.push_back({size_t(layer_capacity_) * sizeof(GpuOverlayState),
                      extras.size() * sizeof(GpuOverlayState), extras.data()});
  }
  s = staging_->upload(overlays_, pieces);
  if (s.isOk()) uploaded_bytes_ += (overlays.size() + extras.size()) * sizeof(GpuOverlayState);
  return s;
}

Status GpuCulledPath::uploadChanges(const GlInfo& info, const CrowdManager& crowd) {
  const CrowdExport exported(crowd);
  std::vector<DenseRange>& changed = changed_runs_;
  std::vector<DenseRange>& placed = placed_runs_;
  exported.changedSince(version_, &changed, &placed);
  size_t total = 0;
  for (const DenseRange& c : changed) total += c.count;
  changed_handles_.resize(total);
  // The changed instances' state, exported by the crowd's workers straight into the staging
  // ring (one chunk: some 29,000 instances) or through changed_bytes_ (more).
  std::vector<BufferPiece>& pieces = pieces_;
  pieces.clear();
  appendRunPieces(changed, 0, sizeof(GpuInstanceState), nullptr, &pieces);
  Status up = uploadWritten(*staging_, state_, &pieces, total * sizeof(GpuInstanceState),
                            &changed_bytes_, [&](uint8_t* out) {
                              exported.state(changed, reinterpret_cast<GpuInstanceState*>(out),
                                             changed_handles_.data());
                            });
  if (!up.isOk()) return up;
  // Motion vectors key what was drawn by handle slot: room for the largest (never less).
  for (const InstanceHandle& h : changed_handles_)
    slots_needed_ = std::max(slots_needed_, (h.id & (HandlePool::kMaxSlots - 1)) + 1);
  uploaded_bytes_ += total * sizeof(GpuInstanceState);

  // Overlays: all of them when the crowd starts or stops holding any or outgrows the buffer,
  // else the changed instances'.
  const uint32_t n = crowd.size();
  if (exported.playsOverlays() != layers_ ||
      (layers_ && (n > layer_capacity_ || exported.writesExtraLayers() != extras_))) {
    Status s = uploadOverlays(info, crowd);
    if (!s.isOk()) return s;
  } else if (layers_) {
    // The overlays, then their extra layers (after the overlays' capacity).
    pieces.clear();
    appendRunPieces(changed, 0, sizeof(GpuOverlayState), nullptr, &pieces);
    if (extras_)
      appendRunPieces(changed, size_t(layer_capacity_) * sizeof(GpuOverlayState),
                      kExtraLayerRecords * sizeof(GpuOverlayState), nullptr, &pieces);
    const size_t records = total * (extras_ ? 1 + kExtraLayerRecords : 1);
    up = uploadWritten(*staging_, overlays_, &pieces, records * sizeof(GpuOverlayState),
                       &changed_bytes_, [&](uint8_t* out) {
                         GpuOverlayState* overlays = reinterpret_cast<GpuOverlayState*>(out);
                         exported.overlays(changed, overlays);
                         if (extras_) exported.extraLayers(changed, overlays + total);
                       });
    if (!up.isOk()) return up;
    uploaded_bytes_ += records * sizeof(GpuOverlayState);
  }
  if (!placed.empty()) {  // Views seeded at the last upload start over there only.
    placed_.swap(placed);  // The last frame's list's memory reused next frame.
    placed_upload_ = ++uploads_;
  }
  version_ = exported.stateVersion();
  instances_ = n;
  return Status::ok();
}

Status GpuCulledPath::prepareView(const PathFrame& f) {
  view_ = views_.find(f.view->identity(), frame_);
  GpuViewSlot& v = *view_;
  v.last_frame = frame_;
  Status s = v.ensureInstances(capacity_);
  if (!s.isOk()) return s;
  if (v.seeded_upload != uploads_) {  // The view's LODs as its CPU selection left them:
    std::vector<uint32_t>& lods = seed_lods_;
    if (v.seeded_upload + 1 == uploads_ && placed_upload_ == uploads_) {
      // Where other instances sit since its last upload (those LODs alone: churn costs what
      // changed, not the crowd's size). A view that never selected on the CPU holds LOD 0
      // everywhere, where the culling pass starts a place over by itself (it keeps the handle
      // of the instance it saw there): the main view and shadow cascades, say, need no seed.
      if (f.view->selectionCount() == 0) {
        v.seeded_upload = uploads_;
        return Status::ok();
      }
      size_t total = 0;
      for (const DenseRange& d : placed_) total += d.count;
      lods.assign(total, 0u);
      CrowdExport::lods(*f.view, placed_, lods.data());
      s = v.seed(*staging_, lods, placed_, uploads_);
      seed_bytes_ = total * sizeof(glm::uvec2);
    } else {  // or everywhere.
      CrowdExport::lods(*f.view, &lods);
      seed_bytes_ = uint64_t(instances_) * sizeof(glm::uvec2);
      s = v.seed(*staging_, lods, instances_, uploads_);
    }
    if (!s.isOk()) return s;
  }
  return Status::ok();
}

}  // namespace si::detail
