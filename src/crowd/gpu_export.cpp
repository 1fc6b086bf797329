// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// si::CrowdExport: the crowd's state for GPU-driven culling (instances, overlays, clips, what
// changed, and per view the frame's parameters and LODs), as the shaders read them
// (si/crowd/gpu_crowd_state.h).
#include "si/crowd/crowd_export.h"

#include "crowd/crowd_state.h"
#include "crowd/dense_runs.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/crowd_view.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace si {

namespace detail {

CullParams crowdCullParams(const CrowdState& st, const Camera& camera) {
  const CrowdDesc& desc = st.owner->desc();
  CullParams p;
  p.planes = camera.frustumPlanes();
  p.radius = st.radius;
  p.max_distance_radii = desc.max_distance_radii;
  p.hysteresis = desc.lod_hysteresis_ratio;
  p.lod_count = desc.lod_count;
  if (desc.lod_mode == LodMode::kScreenError) {
    // Projected error of LOD l + 1 at distance d: error x scale x K / d pixels, with K = half
    // the viewport's height x projection[1][1] (1 / tan(fov_y / 2)). It is within the budget
    // from d = error x scale x K / budget on: in radii (radius x scale), a line that does not
    // depend on the instance's scale. The same selection arithmetic then runs on CPU and GPU.
    // A camera without a usable projection or viewport keeps every instance at LOD 0. A
    // y-flipped projection (a render texture) negates projection[1][1]: its magnitude scales.
    // An orthographic one (a shadow cascade; projection[3][3] 1) projects an error to the same
    // pixels at every distance: error x scale x K, K with projection[1][1] = 2 / height; a
    // level is then within the budget everywhere (line 0) or nowhere, judged at scale 1.
    const double k =
        0.5 * double(camera.viewport_height_pixels) * std::fabs(double(camera.projection[1][1]));
    const bool orthographic = camera.projection[3][3] == 1.0f && camera.projection[2][3] == 0.0f;
    const double most = double(std::numeric_limits<float>::max());
    for (uint32_t l = 0; l + 1 < desc.lod_count && l < 7; ++l) {
      const double error = double(desc.lod_errors_units[l + 1]);
      const double budget = double(desc.pixel_error_budget);
      const double line = orthographic ? (error * k <= budget ? 0.0 : most)
                                       : error * k / (budget * double(st.radius));
      p.lod_lines[l] = k > 0.0 && line >= 0.0 && line < most ? float(line) : float(most);
    }
  } else {
    for (size_t l = 0; l < st.lod_lines.size() && l < 7; ++l) p.lod_lines[l] = st.lod_lines[l];
  }
  p.animation_lod_start = detail::animationLodStart(desc);
  p.animation_step_seconds = detail::animationStepSeconds(desc);
  return p;
}

}  // namespace detail

namespace {

// A playback as the GPU reads it, into the five fields of a state struct: its start on the
// crowd clock and in the clip, the clip, the loop mode and the speed.
void exportPlayback(const detail::Playback& p, double* start_clock, double* start_time,
                    uint32_t* clip, uint32_t* loop, float* speed) {
  *start_clock = p.start_clock;
  *start_time = p.start_time;
  *clip = p.clip;
  *loop = uint32_t(p.loop);
  *speed = p.speed;
}

// Built on the stack and stored once: `out` may be write-combined memory (never read).
void exportInstance(const detail::InstanceStore& st, uint32_t i, GpuInstanceState* out) {
  GpuInstanceState g{};
  const glm::dvec3 p = st.positions.get(i);
  for (int k = 0; k < 3; ++k) g.position[k] = p[k];
  const glm::quat q = st.rotations.get(i);
  g.rotation[0] = q.x, g.rotation[1] = q.y, g.rotation[2] = q.z, g.rotation[3] = q.w;
  g.scale = st.scales[i];
  g.color = st.colors[i];
  g.variation_mask = st.masks[i];
  g.lod = st.views[0].lods[i];
  exportPlayback(st.playback[i], &g.start_clock, &g.start_time, &g.clip, &g.loop, &g.speed);
  g.fading = st.fade_duration[i] > 0.0 ? 1u : 0u;
  g.fade_start = st.fade_start[i];
  g.fade_duration = st.fade_duration[i];
  exportPlayback(st.fade_from[i], &g.from_start_clock, &g.from_start_time, &g.from_clip,
                 &g.from_loop, &g.from_speed);
  g.handle = st.dense_handles[i].id;
  g.placement = st.placements[i];
  g.live_pose = st.live_slot[i];  // detail::kNoLivePose is kGpuNoLivePose.
  *out = g;
}

GpuOverlayState exportedOverlay(const detail::OverlayState& o) {
  GpuOverlayState g{};
  if (!o.active) return g;
  exportPlayback(o.playback, &g.start_clock, &g.start_time, &g.clip, &g.loop, &g.speed);
  g.fade_start = o.fade_start;
  g.fade_duration = o.fade_duration;
  g.mask = o.mask;
  g.weight_from = o.weight_from;
  g.weight_to = o.weight_to;
  g.active = 1u;
  return g;
}

// Extra layer `k` of `o` as an overlay state of its own.
GpuOverlayState exportedExtraLayer(const detail::OverlayState& o, uint32_t k) {
  GpuOverlayState g = exportedOverlay(o);
  if (!o.active) return g;
  const detail::ExtraLayer& e = o.extra[k];
  exportPlayback(e.playback, &g.start_clock, &g.start_time, &g.clip, &g.loop, &g.speed);
  g.weight_from = e.weight_from;
  g.weight_to = e.weight_to;
  return g;
}

}  // namespace

namespace {

// Asks for the lines state() reads of instance `i`: a dozen arrays at one index.
void prefetchInstance(const detail::InstanceStore& st, uint32_t i) {
  const uint32_t k = i % detail::kColumnBlock;
  const detail::DVec3Block& p = st.positions.blockOf(i);
  detail::prefetchLine(&p.x[k]), detail::prefetchLine(&p.y[k]), detail::prefetchLine(&p.z[k]);
  const detail::QuatBlock& q = st.rotations.blockOf(i);
  detail::prefetchLine(&q.w[k]), detail::prefetchLine(&q.y[k]);
  detail::prefetchLine(&st.scales[i]), detail::prefetchLine(&st.colors[i]);
  detail::prefetchLine(&st.masks[i]), detail::prefetchLine(&st.views[0].lods[i]);
  detail::prefetchLine(&st.playback[i]), detail::prefetchLine(&st.fade_from[i]);
  detail::prefetchLine(&st.fade_start[i]), detail::prefetchLine(&st.fade_duration[i]);
  detail::prefetchLine(&st.dense_handles[i]), detail::prefetchLine(&st.placements[i]);
  detail::prefetchLine(&st.live_slot[i]);
}

// `body(overlay, position)` for the overlays of `runs` (`total` indices), prefetched, on the
// crowd's workers.
template <class Body>
void walkOverlays(detail::CrowdState& crowd, Span<const DenseRange> runs, size_t total,
                  const Body& body) {
  const detail::InstanceStore& st = crowd.store;
  detail::walkRuns(
      runs, total, detail::crowdParallelFor(crowd),
      [&st](uint32_t i) {
        detail::prefetchLine(&st.overlays[i]);
        detail::prefetchLine(&st.overlays[i].extra);
      },
      [&st, &body](uint32_t i, size_t p) { body(st.overlays[i], p); });
}

}  // namespace

// The number of indices in `runs` when the crowd holds every one and there is somewhere to
// write them, else 0: what every ranged export checks (it writes nothing otherwise).
size_t CrowdExport::indicesIn(Span<const DenseRange> runs, const void* out) const {
  const uint32_t size = crowd_->size();
  if (!crowd_->state_ || out == nullptr) return 0;
  size_t total = 0;
  for (const DenseRange& r : runs) {
    if (r.first > size || r.count > size - r.first) return 0;
    total += r.count;
  }
  return total;
}

uint64_t CrowdExport::stateVersion() const {
  return crowd_->state_ ? crowd_->state_->store.version : 0;
}

void CrowdExport::state(std::vector<GpuInstanceState>* out,
                        std::vector<InstanceHandle>* handles) const {
  const uint32_t n = crowd_->size();
  out->resize(n);
  if (n == 0) {
    if (handles != nullptr) handles->clear();
    return;
  }
  const DenseRange all{0, n};
  state(Span<const DenseRange>(&all, 1), out->data(), nullptr);
  if (handles != nullptr) *handles = crowd_->state_->store.dense_handles;
}

void CrowdExport::state(Span<const DenseRange> runs, GpuInstanceState* out,
                        InstanceHandle* handles) const {
  const size_t total = indicesIn(runs, out);
  if (total == 0) return;
  detail::CrowdState& crowd = *crowd_->state_;
  const detail::InstanceStore& st = crowd.store;
  detail::walkRuns(
      runs, total, detail::crowdParallelFor(crowd), [&st](uint32_t i) { prefetchInstance(st, i); },
      [&st, out, handles](uint32_t i, size_t p) {
        exportInstance(st, i, out + p);
        if (handles != nullptr) handles[p] = st.dense_handles[i];
      });
}

void CrowdExport::changedSince(uint64_t since, std::vector<DenseRange>* changed,
                               std::vector<DenseRange>* placed) const {
  const uint32_t n = crowd_->size();
  if (changed != nullptr) changed->clear();
  if (placed != nullptr) placed->clear();
  if (n == 0) return;
  const detail::InstanceStore& st = crowd_->state_->store;
  // The changes since the last caller's version, kept as they were made; else the log's or
  // the stamps'.
  if (st.pending.take(since, st.version, n, changed, placed)) return;
  if (st.change_log.answers(since, n)) {  // A few changes since: not every stamp read.
    st.change_log.since(since, n, changed, placed);
    return;
  }
  if (changed != nullptr) detail::scanStamps(st.changed_at, st.chunk_changed_at, since, n, changed);
  if (placed != nullptr) detail::scanStamps(st.placed_at, st.chunk_placed_at, since, n, placed);
}

Span<const uint8_t> CrowdExport::livePoseTexels() const {
  return crowd_->state_ ? crowd_->state_->store.live.texels() : Span<const uint8_t>();
}
uint32_t CrowdExport::livePoseFirstTexel() const {
  return crowd_->state_ ? crowd_->state_->store.live.firstTexel() : 0;
}
void CrowdExport::livePoseTexelsChangedSince(uint64_t since, uint32_t* first,
                                             uint32_t* count) const {
  *first = *count = 0;
  if (crowd_->state_) crowd_->state_->store.live.changedTexels(since, first, count);
}
void CrowdExport::copyLivePoseTexels(uint32_t first, uint32_t count, uint8_t* out) const {
  const Span<const uint8_t> texels = livePoseTexels();
  if (texels.empty() || out == nullptr || count == 0) return;
  const size_t bytes = bytesPerTexel(crowd_->desc().palette->format);
  const size_t total = texels.size() / bytes;
  if (first > total || count > total - first) return;
  const uint8_t* from = texels.data() + size_t(first) * bytes;
  const size_t size = size_t(count) * bytes;
  // Tasks of at least 64 KiB (a thread's start costs microseconds), at most 64, each a whole
  // number of cache lines.
  constexpr size_t kTaskBytes = size_t(64) << 10, kMostTasks = 64, kLine = 64;
  const size_t tasks = std::min(kMostTasks, size / kTaskBytes);
  const ParallelFor run = tasks >= 4 ? detail::crowdWorkers(*crowd_->state_) : ParallelFor();
  if (!run) {
    std::memcpy(out, from, size);
    return;
  }
  const size_t per = (size / tasks + kLine - 1) / kLine * kLine;
  run(uint32_t(tasks), [from, out, size, per](uint32_t t) {
    const size_t at = size_t(t) * per;
    if (at < size) std::memcpy(out + at, from + at, std::min(per, size - at));
  });
}
uint64_t CrowdExport::livePoseVersion() const {
  return crowd_->state_ ? crowd_->state_->store.live.version() : 0;
}
uint32_t CrowdExport::livePoseCount() const {
  return crowd_->state_ ? crowd_->state_->store.live.count() : 0;
}
void CrowdExport::livePoses(std::vector<GpuLivePose>* out) const {
  out->clear();
  if (!crowd_->state_) return;
  const DenseRange all{0, crowd_->state_->store.live.capacity()};
  out->resize(all.count);
  livePoses(Span<const DenseRange>(&all, 1), out->data());
}

void CrowdExport::livePoses(Span<const DenseRange> slots, GpuLivePose* out) const {
  if (!crowd_->state_) return;
  const detail::LivePoses& live = crowd_->state_->store.live;
  size_t p = 0;
  for (const DenseRange& r : slots)
    for (uint32_t slot = r.first; slot < r.first + r.count; ++slot) {
      const detail::LivePoses::Fade& f = live.fadeOf(slot);
      GpuLivePose g{};
      g.fade_start = f.start;
      g.fade_duration = f.duration;
      g.weight_from = f.from;
      g.weight_to = f.to;
      g.first_texel = live.frameTexel(slot);
      const detail::LivePoses::Bounds& b = live.boundsOf(slot);
      g.bounded = b.known ? 1u : 0u;
      if (b.known) {  // Else its bounds stay zero.
        for (int k = 0; k < 3; ++k) {
          g.sphere[k] = b.sphere.center[k];
          g.box_min[k] = b.box.min[k];
          g.box_max[k] = b.box.max[k];
        }
        g.sphere[3] = b.sphere.radius;
      }
      std::memcpy(out + p++, &g, sizeof g);  // One stream of whole slots.
    }
}

bool CrowdExport::playsOverlays() const {
  return crowd_->state_ && crowd_->state_->store.overlay_count > 0;
}

void CrowdExport::overlays(std::vector<GpuOverlayState>* out) const {
  const uint32_t size = crowd_->size();
  out->clear();
  if (!playsOverlays()) return;
  out->resize(size);
  const DenseRange all{0, size};
  overlays(Span<const DenseRange>(&all, 1), out->data());
}

void CrowdExport::overlays(Span<const DenseRange> runs, GpuOverlayState* out) const {
  const size_t total = indicesIn(runs, out);
  if (total > 0)
    walkOverlays(*crowd_->state_, runs, total,
                 [out](const detail::OverlayState& o, size_t p) { out[p] = exportedOverlay(o); });
}

bool CrowdExport::writesExtraLayers() const {
  return playsOverlays() && crowd_->state_->extra_layers;
}

void CrowdExport::extraLayers(std::vector<GpuOverlayState>* out) const {
  const uint32_t size = crowd_->size();
  out->clear();
  if (!writesExtraLayers()) return;
  out->resize(size_t(size) * kExtraLayerRecords);
  const DenseRange all{0, size};
  extraLayers(Span<const DenseRange>(&all, 1), out->data());
}

void CrowdExport::extraLayers(Span<const DenseRange> runs, GpuOverlayState* out) const {
  const size_t total = indicesIn(runs, out);
  if (total > 0)
    walkOverlays(*crowd_->state_, runs, total, [out](const detail::OverlayState& o, size_t p) {
      for (uint32_t k = 0; k < kExtraLayerRecords; ++k)
        out[p * kExtraLayerRecords + k] = exportedExtraLayer(o, k);
    });
}

void CrowdExport::clips(std::vector<GpuClipInfo>* clips, std::vector<double>* frame_times) const {
  const detail::CrowdState* state = crowd_->state_.get();
  const CrowdDesc& desc = crowd_->desc_;
  clips->clear();
  frame_times->clear();
  if (!state) return;
  for (size_t c = 0; c < state->clips.size(); ++c) {
    const detail::ClipTiming& ci = state->clips[c];
    const BakedClip& bc = desc.palette->clips[c];
    GpuClipInfo g{};
    g.duration = ci.duration;
    g.inv_duration = ci.inv_duration;
    g.interval = ci.interval;
    g.inv_interval = ci.inv_interval;
    g.sphere[0] = ci.sphere_center.x, g.sphere[1] = ci.sphere_center.y;
    g.sphere[2] = ci.sphere_center.z, g.sphere[3] = ci.sphere_radius;
    for (int k = 0; k < 3; ++k) g.box_min[k] = bc.bounds.min[k], g.box_max[k] = bc.bounds.max[k];
    g.first_texel = ci.first_texel;
    g.last_interval = ci.last_interval;
    g.uniform_grid = ci.uniform ? 1u : 0u;
    g.frame_count = bc.frame_count;
    g.times_offset = uint32_t(frame_times->size());
    frame_times->insert(frame_times->end(), bc.frame_times_seconds.begin(),
                        bc.frame_times_seconds.end());
    g.modes_offset = 0xFFFFFFFFu;
    if (!bc.interval_modes.empty()) {
      g.modes_offset = uint32_t(frame_times->size());
      for (uint8_t m : bc.interval_modes) frame_times->push_back(double(m));
    }
    clips->push_back(g);
  }
}

CullParams CrowdExport::cullParams(const CrowdView& view, const Camera& camera) {
  const detail::ViewState& v = view.view();
  if (v.crowd == nullptr) return CullParams();
  return detail::viewCullParams(*v.crowd, v, camera);
}

void CrowdExport::lods(const CrowdView& view, std::vector<uint32_t>* out) {
  const detail::ViewState& v = view.view();
  out->clear();
  if (v.crowd == nullptr) return;
  const std::vector<uint8_t>& lods = v.crowd->store.views[v.lane].lods;
  out->assign(lods.begin(), lods.end());
}

void CrowdExport::lods(const CrowdView& view, Span<const DenseRange> runs, uint32_t* out) {
  const detail::ViewState& v = view.view();
  if (v.crowd == nullptr || v.crowd->owner == nullptr) return;
  const size_t total = CrowdExport(*v.crowd->owner).indicesIn(runs, out);
  if (total == 0) return;
  // A byte an index: the calling thread alone (workers cost more than they save at 1M x 1 %).
  const uint8_t* lods = v.crowd->store.views[v.lane].lods.data();
  detail::walkRuns(
      runs, total, ParallelFor(), [lods](uint32_t i) { detail::prefetchLine(lods + i); },
      [lods, out](uint32_t i, size_t p) { out[p] = lods[i]; });
}

}  // namespace si
