// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's uploads in proportion to change: only the instances the crowd changed
// since the last upload (CrowdManager::changedSince) are exported and written, and only where
// other instances sit now do the views start their history over. And the overlays, whole. Every
// write goes through the staging ring (resources/upload_ring.h): the last frame's passes may
// still be reading these buffers. Each view's LODs and flags are seeded after an upload.
#include <algorithm>

#include "gl/paths/gpu_culled_path.h"
#include "gl/resources/gl_allocation.h"
#include "si/crowd/handle_pool.h"

namespace si::detail {

Status GpuCulledPath::uploadOverlays(const CrowdManager& crowd) {
  std::vector<GpuOverlayState> overlays, extras;
  crowd.exportGpuOverlays(&overlays);
  layers_ = !overlays.empty();
  extras_ = layers_ && crowd.writesExtraLayers();
  if (!layers_) return Status::ok();
  Status s = Status::ok();
  const uint32_t copies = extras_ ? 1 + kExtraLayerRecords : 1;
  if (overlays.size() > layer_capacity_ || overlays_ == kNoObject || copies > layer_copies_) {
    layer_capacity_ = 0;
    const size_t capacity = overlays.size() * copies;
    s = createBuffer(&overlays_, capacity * sizeof(GpuOverlayState), nullptr,
                     GL_DYNAMIC_STORAGE_BIT, "GPU culling: the overlays");
    if (s.isOk())
      s = createBuffer(&layers_out_, capacity * kLayerRecordSize, nullptr,
                       GL_DYNAMIC_STORAGE_BIT, "GPU culling: the layer records");
    if (!s.isOk()) return s;
    layer_capacity_ = uint32_t(overlays.size());
    layer_copies_ = copies;
  }
  std::vector<BufferPiece> pieces{{0, overlays.size() * sizeof(GpuOverlayState), overlays.data()}};
  if (extras_) {  // After the overlays' capacity (cull.comp.glsl's u_extras).
    crowd.exportGpuExtraLayers(&extras);
    pieces.push_back({size_t(layer_capacity_) * sizeof(GpuOverlayState),
                      extras.size() * sizeof(GpuOverlayState), extras.data()});
  }
  s = staging_.upload(overlays_, pieces);
  if (s.isOk()) uploaded_bytes_ += (overlays.size() + extras.size()) * sizeof(GpuOverlayState);
  return s;
}

Status GpuCulledPath::uploadChanges(const CrowdManager& crowd) {
  std::vector<DenseRange> changed, placed;
  crowd.changedSince(version_, &changed, &placed);
  size_t total = 0;
  for (const DenseRange& c : changed) total += c.count;
  changed_state_.resize(total);
  changed_handles_.resize(total);
  std::vector<BufferPiece> pieces;
  size_t at = 0;
  for (const DenseRange& c : changed) {
    crowd.exportGpuState(c, changed_state_.data() + at, changed_handles_.data() + at);
    pieces.push_back({size_t(c.first) * sizeof(GpuInstanceState),
                      size_t(c.count) * sizeof(GpuInstanceState), changed_state_.data() + at});
    at += c.count;
  }
  // Motion vectors key what was drawn by handle slot: room for the largest (never less).
  for (const InstanceHandle& h : changed_handles_)
    slots_needed_ = std::max(slots_needed_, (h.id & (HandlePool::kMaxSlots - 1)) + 1);
  Status up = staging_.upload(state_, pieces);
  if (!up.isOk()) return up;
  uploaded_bytes_ += total * sizeof(GpuInstanceState);

  // Overlays: all of them when the crowd starts or stops holding any or outgrows the buffer,
  // else the changed instances'.
  const uint32_t n = crowd.size();
  if (crowd.playsOverlays() != layers_ ||
      (layers_ && (n > layer_capacity_ || crowd.writesExtraLayers() != extras_))) {
    Status s = uploadOverlays(crowd);
    if (!s.isOk()) return s;
  } else if (layers_) {
    changed_overlays_.resize(total);
    if (extras_) changed_extras_.resize(total * kExtraLayerRecords);
    pieces.clear();
    at = 0;
    for (const DenseRange& c : changed) {
      crowd.exportGpuOverlays(c, changed_overlays_.data() + at);
      pieces.push_back({size_t(c.first) * sizeof(GpuOverlayState),
                        size_t(c.count) * sizeof(GpuOverlayState), changed_overlays_.data() + at});
      if (extras_) {  // Its extra layers, after the overlays' capacity.
        GpuOverlayState* out = changed_extras_.data() + at * kExtraLayerRecords;
        crowd.exportGpuExtraLayers(c, out);
        pieces.push_back({(size_t(layer_capacity_) + size_t(c.first) * kExtraLayerRecords) *
                              sizeof(GpuOverlayState),
                          size_t(c.count) * kExtraLayerRecords * sizeof(GpuOverlayState), out});
      }
      at += c.count;
    }
    up = staging_.upload(overlays_, pieces);
    if (!up.isOk()) return up;
    uploaded_bytes_ += total * (extras_ ? 1 + kExtraLayerRecords : 1) * sizeof(GpuOverlayState);
  }
  if (!placed.empty()) {  // Views seeded at the last upload start over there only.
    placed_ = std::move(placed);
    placed_upload_ = ++uploads_;
  }
  version_ = crowd.stateVersion();
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
    std::vector<uint32_t> lods;
    f.view->exportGpuLods(&lods);
    if (v.seeded_upload + 1 == uploads_ && placed_upload_ == uploads_)
      s = v.seed(staging_, lods, placed_, uploads_);     // where other instances sit since its last
    else                                                 // upload,
      s = v.seed(staging_, lods, instances_, uploads_);  // or everywhere.
    if (!s.isOk()) return s;
  }
  return Status::ok();
}

}  // namespace si::detail
