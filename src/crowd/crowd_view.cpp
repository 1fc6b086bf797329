// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdView: one camera's selection of a crowd (its own lane of LODs and motion-vector slots in
// the crowd's store, its own frame), and the selection plumbing CrowdManager::update shares.
#include "si/crowd/crowd_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "core/str_cat.h"
#include "crowd/crowd_state.h"
#include "si/crowd/crowd_manager.h"

namespace si {

namespace detail {

CrowdState::CrowdState() = default;

CrowdState::~CrowdState() {
  for (ViewState* v : views) v->crowd = nullptr;
}

void resetSelection(const CrowdDesc& desc, ViewState* v) {
  v->frame = CrowdFrame();
  v->frame.bucket_offsets.assign(size_t(desc.lod_count) * desc.sub_mesh_count + 1, 0);
  v->frame.run_offsets.assign(size_t(desc.lod_count) * desc.sub_mesh_count + 1, 0);
  v->camera = v->previous_camera = Camera();
  v->selected = false;
  v->identity = nextStateVersion();
  v->selections = 0;
  v->sub_mesh_count = desc.sub_mesh_count;
  v->lod_count = desc.lod_count;
}

ParallelFor crowdParallelFor(CrowdState& st) {
  if (st.store.size() <= kChunkInstances) return ParallelFor();
  return crowdWorkers(st);
}

ParallelFor crowdWorkers(CrowdState& st) {
  const CrowdDesc& desc = st.owner->desc();
  if (desc.worker_threads == 1) return ParallelFor();
  WorkerPool* pool = nullptr;  // One pointer: the std::function does not allocate.
  {
    std::lock_guard<std::mutex> lock(st.pool_mutex);
    if (!st.pool) {
      const uint32_t hw = std::max(1u, std::thread::hardware_concurrency());
      st.pool = std::make_unique<WorkerPool>(desc.worker_threads == 0 ? std::min(hw, 16u)
                                                                      : desc.worker_threads);
    }
    pool = st.pool.get();
  }
  return [pool](uint32_t count, const ParallelTask& task) { pool->run(count, task); };
}

const ParallelFor& taskRunner(CrowdState& crowd, const ParallelFor& given, ParallelFor* own) {
  if (given) return given;
  *own = crowdParallelFor(crowd);
  return *own;
}

CullParams viewCullParams(const CrowdState& crowd, const ViewState& view, const Camera& camera) {
  CullParams p = crowdCullParams(crowd, camera);
  // The view's own rules over the crowd's lines.
  const float scale = view.desc.lod_distance_scale == 0.0f ? 1.0f : view.desc.lod_distance_scale;
  if (scale != 1.0f)
    for (uint32_t l = 0; l + 1 < p.lod_count && l < 7; ++l)
      p.lod_lines[l] = float(std::min(double(p.lod_lines[l]) * double(scale),
                                      double(std::numeric_limits<float>::max())));
  if (view.desc.max_distance_radii != 0.0f) p.max_distance_radii = view.desc.max_distance_radii;
  p.lod_bias = view.desc.lod_bias;
  return p;
}

FrameInputs frameInputs(CrowdState& st, const ViewState& view, const Camera& camera,
                        const ParallelFor& parallel_for, bool simulate) {
  const CrowdManager& crowd = *st.owner;
  const CrowdDesc& desc = crowd.desc();
  FrameInputs in;
  in.palette = desc.palette;
  in.clips = &st.clips;
  in.params = viewCullParams(st, view, camera);
  in.camera_position = camera.position;
  in.clock = st.clock;
  in.sub_mesh_count = desc.sub_mesh_count;
  in.impostor_lod = desc.impostor_lod;
  in.parallel_for = &parallel_for;
  in.markers = &st.markers;
  in.root_motion = st.store.root_motion_count > 0;
  in.previous_records = view.desc.previous_records;
  in.layers = st.store.overlay_count > 0;
  in.extra_layers = in.layers && st.extra_layers;
  in.lane = view.lane;
  in.lod_bias = in.params.lod_bias;
  in.simulate = simulate;
  if (simulate) {
    const uint32_t chunks = chunkCount(st.store.size());
    if (st.chunk_events.size() < chunks) st.chunk_events.resize(chunks);
    in.chunk_events = &st.chunk_events;
  }
  return in;
}

void selectView(const FrameInputs& in, const Camera& camera, ViewState* v) {
  buildFrame(in, v->crowd->store, &v->frame);
  v->previous_camera = v->selected ? v->camera : camera;
  v->camera = camera;
  v->selected = true;
  ++v->selections;
}

void gatherEvents(CrowdState* st) {
  st->events.clear();
  const uint32_t chunks = chunkCount(st->store.size());
  for (uint32_t c = 0; c < chunks; ++c)
    st->events.insert(st->events.end(), st->chunk_events[c].begin(), st->chunk_events[c].end());
}

// Leaves the crowd the view is attached to (its lane freed), if any.
static void detach(ViewState* v) {
  CrowdState* crowd = v->crowd;
  if (crowd == nullptr) return;
  crowd->views.erase(std::remove(crowd->views.begin(), crowd->views.end(), v), crowd->views.end());
  crowd->store.releaseView(v->lane);
  v->crowd = nullptr;
}

}  // namespace detail

using detail::ViewState;

CrowdView::CrowdView() : state_(std::make_unique<ViewState>()) {}
CrowdView::~CrowdView() {
  if (state_ && state_->lane != 0) detail::detach(state_.get());  // A crowd's own stays.
}
CrowdView::CrowdView(CrowdView&& other) noexcept = default;  // The ViewState does not move.
CrowdView& CrowdView::operator=(CrowdView&& other) noexcept {
  if (this == &other) return *this;
  if (state_ && state_->lane != 0) detail::detach(state_.get());
  state_ = std::move(other.state_);
  return *this;
}

const ViewState& CrowdView::emptyView() {
  static const ViewState empty;
  return empty;
}
const ViewState& CrowdView::view() const { return state_ ? *state_ : emptyView(); }

Status CrowdView::init(CrowdManager& crowd, const CrowdViewDesc& desc) {
  if (!crowd.state_)
    return {StatusCode::kInvalidArgument, "CrowdView::init: the crowd needs init() first"};
  if (desc.lod_bias > 7)
    return {StatusCode::kInvalidArgument,
            detail::strCat("CrowdViewDesc.lod_bias must be at most 7 (it is ", desc.lod_bias, ")")};
  if (!std::isfinite(desc.lod_distance_scale) || desc.lod_distance_scale < 0.0f)
    return {StatusCode::kInvalidArgument,
            "CrowdViewDesc.lod_distance_scale must be finite and >= 0 (0 means 1)"};
  if (!std::isfinite(desc.max_distance_radii))
    return {StatusCode::kInvalidArgument, "CrowdViewDesc.max_distance_radii must be finite"};
  if (!state_) state_ = std::make_unique<ViewState>();
  ViewState& v = *state_;
  detail::detach(&v);
  detail::CrowdState& st = *crowd.state_;
  v.crowd = &st;
  v.lane = st.store.addView();
  v.desc = desc;
  detail::resetSelection(crowd.desc(), &v);
  st.views.push_back(&v);
  return Status::ok();
}

bool CrowdView::attached() const { return view().crowd != nullptr; }
const CrowdManager* CrowdView::crowd() const {
  return view().crowd != nullptr ? view().crowd->owner : nullptr;
}
const CrowdViewDesc& CrowdView::desc() const { return view().desc; }
uint32_t CrowdView::subMeshCount() const { return view().sub_mesh_count; }
uint32_t CrowdView::lodCount() const { return view().lod_count; }

Status CrowdView::select(const Camera& camera, const ParallelFor& parallel_for) {
  if (!attached())
    return {StatusCode::kInvalidArgument,
            "CrowdView::select: the view is not attached to a crowd (init() it; a crowd destroyed "
            "or init() again detaches its views)"};
  ParallelFor own;
  const detail::FrameInputs in =
      detail::frameInputs(*state_->crowd, *state_, camera,
                          detail::taskRunner(*state_->crowd, parallel_for, &own), false);
  detail::selectView(in, camera, state_.get());
  return Status::ok();
}

const CrowdFrameStats& CrowdView::stats() const { return view().frame.stats; }
uint32_t CrowdView::bucketCount() const {
  return uint32_t(std::max<size_t>(view().frame.bucket_offsets.size(), 1) - 1);
}
const std::vector<uint32_t>& CrowdView::bucketOffsets() const { return view().frame.bucket_offsets; }
const std::vector<uint32_t>& CrowdView::bucketEntries() const {
  if (!state_) return emptyView().frame.bucket_entries;
  if (!state_->frame.entries_valid) detail::expandBucketEntries(&state_->frame);
  return state_->frame.bucket_entries;
}
const std::vector<uint32_t>& CrowdView::bucketRunOffsets() const { return view().frame.run_offsets; }
const std::vector<RecordRun>& CrowdView::bucketRuns() const { return view().frame.runs; }
Span<const InstanceRecord> CrowdView::records() const {
  const detail::CrowdFrame& f = view().frame;
  return Span<const InstanceRecord>(f.records.data(), f.stats.visible);
}
Span<const InstanceHandle> CrowdView::visibleHandles() const {
  const detail::CrowdFrame& f = view().frame;
  return Span<const InstanceHandle>(f.visible_handles.data(), f.stats.visible);
}
Span<const LayerRecord> CrowdView::layerRecords() const {
  const detail::CrowdFrame& f = view().frame;
  return f.layers ? Span<const LayerRecord>(f.layer_records.data(), f.stats.visible)
                  : Span<const LayerRecord>();
}
Span<const LayerRecord> CrowdView::extraLayerRecords() const {
  const detail::CrowdFrame& f = view().frame;
  return f.extras ? Span<const LayerRecord>(f.extra_layer_records.data(),
                                            size_t(f.stats.visible) * kExtraLayerRecords)
                  : Span<const LayerRecord>();
}
Span<const InstanceRecord> CrowdView::previousRecords() const {
  const ViewState& v = view();
  if (!v.desc.previous_records) return {};
  return Span<const InstanceRecord>(v.frame.previous_records.data(), v.frame.previous_visible);
}
Span<const uint32_t> CrowdView::previousRecordIndices() const {
  const ViewState& v = view();
  if (!v.desc.previous_records) return {};
  return Span<const uint32_t>(v.frame.previous_index.data(), v.frame.stats.visible);
}
Span<const LayerRecord> CrowdView::previousLayerRecords() const {
  const ViewState& v = view();
  if (!v.desc.previous_records || !v.frame.previous_layers) return {};
  return Span<const LayerRecord>(v.frame.previous_layer_records.data(), v.frame.previous_visible);
}
Span<const LayerRecord> CrowdView::previousExtraLayerRecords() const {
  const ViewState& v = view();
  if (!v.desc.previous_records || !v.frame.previous_extras) return {};
  return Span<const LayerRecord>(v.frame.previous_extra_layer_records.data(),
                                 size_t(v.frame.previous_visible) * kExtraLayerRecords);
}
uint64_t CrowdView::identity() const { return view().identity; }
uint64_t CrowdView::selectionCount() const {
  return view().selections;
}

const Camera& CrowdView::camera() const { return view().camera; }
const Camera& CrowdView::previousCamera() const { return view().previous_camera; }

Status CrowdView::lodOf(InstanceHandle h, uint32_t* lod) const {
  const ViewState& v = view();
  if (v.crowd == nullptr)
    return {StatusCode::kInvalidArgument, "CrowdView::lodOf: the view is not attached to a crowd"};
  const detail::InstanceStore& st = v.crowd->store;
  uint32_t i = 0;
  Status s = st.denseIndex(h, &i);
  if (s.isOk() && lod != nullptr)
    *lod = std::min(uint32_t(st.views[v.lane].lods[i]) + v.desc.lod_bias,
                    v.lod_count - 1);
  return s;
}

}  // namespace si
