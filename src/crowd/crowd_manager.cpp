// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager: the public API over the instance store (instance_store.h), the per-frame work
// (frame_builder.h) and the crowd clock.
#include "si/crowd/crowd_manager.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

#include "core/str_cat.h"
#include "crowd/crowd_state.h"

namespace si {
using detail::kMaxLods;
using detail::strCat;

// What an uninitialized (or moved-from) crowd reports.
const detail::CrowdState& CrowdManager::emptyState() {
  static const detail::CrowdState empty;
  return empty;
}

CrowdManager::CrowdManager() = default;
CrowdManager::~CrowdManager() = default;
CrowdManager::CrowdManager(CrowdManager&& other) noexcept
    : state_(std::move(other.state_)), desc_(std::move(other.desc_)) {
  if (state_) state_->owner = this;
}
CrowdManager& CrowdManager::operator=(CrowdManager&& other) noexcept {
  if (this == &other) return *this;
  state_ = std::move(other.state_);  // The old state, if any, detaches its views.
  desc_ = std::move(other.desc_);
  if (state_) state_->owner = this;
  return *this;
}

CrowdDesc resolveDefaults(const CrowdDesc& in) {
  CrowdDesc d = in;
  if (d.lod_count == 0) d.lod_count = 1;
  if (d.character_radius == 0.0f && d.palette != nullptr)
    for (const BakedClip& c : d.palette->clips)
      d.character_radius = std::max(d.character_radius, c.bounding_sphere.radius);
  if (d.lod_distances_radii.empty() && d.lod_count > 1) {
    float line = 20.0f;
    for (uint32_t l = 1; l < d.lod_count; ++l) {
      d.lod_distances_radii.push_back(line);
      line = l == 1 ? 60.0f : line * 3.0f;
    }
  }
  if (d.max_distance_radii == 0.0f) d.max_distance_radii = 100.0f;
  if (d.lod_hysteresis_ratio == 0.0f) d.lod_hysteresis_ratio = 0.05f;
  if (d.animation_lod_rate_hz == 0.0f) d.animation_lod_rate_hz = 10.0f;
  if (d.lod_mode == LodMode::kDefault) d.lod_mode = LodMode::kDistance;
  if (d.pixel_error_budget == 0.0f) d.pixel_error_budget = 1.0f;
  return d;
}

const char* lodModeName(LodMode mode) {
  switch (mode) {
    case LodMode::kDefault: return "default";
    case LodMode::kDistance: return "distance";
    case LodMode::kScreenError: return "screen-error";
  }
  return "unknown";
}

// How LODs are chosen, as init() and setLodMode() accept it.
static Status checkLodMode(LodMode mode, float budget, uint32_t lod_count,
                           const std::vector<float>& errors) {
  if (mode != LodMode::kDistance && mode != LodMode::kScreenError)
    return {StatusCode::kInvalidArgument, "CrowdDesc.lod_mode is unknown"};
  if (!std::isfinite(budget) || budget <= 0.0f)
    return {StatusCode::kInvalidArgument, "CrowdDesc.pixel_error_budget must be finite and > 0"};
  if (errors.empty() && mode == LodMode::kScreenError)
    return {StatusCode::kInvalidArgument,
            "CrowdDesc.lod_errors_units is needed for LodMode::kScreenError (si::lodErrorsByLevel)"};
  if (!errors.empty() && errors.size() != lod_count)
    return {StatusCode::kInvalidArgument,
            strCat("CrowdDesc.lod_errors_units needs lod_count = ", lod_count, " values, has ",
                   errors.size())};
  for (size_t l = 0; l < errors.size(); ++l)
    if (!std::isfinite(errors[l]) || errors[l] < 0.0f || (l > 0 && errors[l] < errors[l - 1]))
      return {StatusCode::kInvalidArgument,
              "CrowdDesc.lod_errors_units must be finite, >= 0 and non-decreasing"};
  return Status::ok();
}

// The LOD and far lines of CrowdDesc, as init() and setLodDistances() accept them.
static Status checkLodLines(uint32_t lod_count, Span<const float> lines, float max_distance_radii) {
  if (lines.size() != lod_count - 1)
    return {StatusCode::kInvalidArgument,
            strCat("CrowdDesc.lod_distances_radii needs lod_count - 1 = ", lod_count - 1,
                   " distances, has ", lines.size())};
  for (size_t i = 0; i < lines.size(); ++i)
    if (!(lines[i] > (i ? lines[i - 1] : 0.0f)) || !std::isfinite(lines[i]))
      return {StatusCode::kInvalidArgument,
              "CrowdDesc.lod_distances_radii must be positive and increasing"};
  if (!std::isfinite(max_distance_radii))
    return {StatusCode::kInvalidArgument, "CrowdDesc.max_distance_radii must be finite"};
  return Status::ok();
}

Status CrowdManager::init(const CrowdDesc& in_desc) {
  const CrowdDesc d = resolveDefaults(in_desc);
  Status s;
  if (d.palette == nullptr || d.palette->clips.empty())
    return {StatusCode::kInvalidArgument, "CrowdDesc.palette must be a palette with clips"};
  s = d.palette->validate();  // A palette from anywhere plays as safely as a bake.
  if (!s.isOk()) return {StatusCode::kInvalidArgument, "CrowdDesc.palette: " + s.message()};
  if (d.sub_mesh_count < 1 || d.sub_mesh_count > 32)
    return {StatusCode::kInvalidArgument, "CrowdDesc.sub_mesh_count must be 1 to 32"};
  if (d.lod_count > kMaxLods)
    return {StatusCode::kInvalidArgument, "CrowdDesc.lod_count must be at most 8"};
  if (d.impostor_lod != 0 && d.impostor_lod + 1 != d.lod_count)
    return {StatusCode::kInvalidArgument,
            strCat("CrowdDesc.impostor_lod must be 0 (none) or the last level, lod_count - 1 = ",
                   d.lod_count - 1, " (it is ", d.impostor_lod, ")")};
  if (!std::isfinite(d.character_radius) || d.character_radius <= 0.0f)
    return {StatusCode::kInvalidArgument, "CrowdDesc.character_radius must be finite and > 0"};
  s = checkLodLines(d.lod_count, d.lod_distances_radii, d.max_distance_radii);
  if (!s.isOk()) return s;
  if (!std::isfinite(d.lod_hysteresis_ratio) ||
      d.lod_hysteresis_ratio < 0.0f || d.lod_hysteresis_ratio >= 1.0f)
    return {StatusCode::kInvalidArgument,
            strCat("CrowdDesc.lod_hysteresis_ratio must be finite and in [0, 1) (it is ",
                   d.lod_hysteresis_ratio, ")")};
  if (!std::isfinite(d.animation_lod_rate_hz) || d.animation_lod_rate_hz <= 0.0f)
    return {StatusCode::kInvalidArgument, "CrowdDesc.animation_lod_rate_hz must be > 0"};
  s = checkLodMode(d.lod_mode, d.pixel_error_budget, d.lod_count, d.lod_errors_units);
  if (!s.isOk()) return s;
  if (d.worker_threads > 256)
    return {StatusCode::kInvalidArgument, "CrowdDesc.worker_threads must be at most 256"};
  if (d.live_pose_capacity > CrowdDesc::kMaxLivePoses)
    return {StatusCode::kInvalidArgument,
            strCat("CrowdDesc.live_pose_capacity must be at most ", CrowdDesc::kMaxLivePoses,
                   " (it is ", d.live_pose_capacity, ")")};
  auto state = std::make_unique<detail::CrowdState>();
  state->store.reset(d.palette);
  s = state->store.live.reset(d.palette, d.live_pose_capacity);
  if (!s.isOk()) return s;
  state->radius = d.character_radius;
  state->lod_lines = d.lod_distances_radii;
  for (const BakedClip& c : d.palette->clips) state->clips.push_back(detail::makeClipTiming(c));
  state->store.clip_timings = &state->clips;  // Stable: the State is not moved.
  // The palette's markers (BakedClip::markers, e.g. from a glTF file) come first.
  state->markers.clip_markers.resize(d.palette->clips.size());
  for (uint32_t c = 0; c < d.palette->clips.size(); ++c)
    for (const AnimationMarker& m : d.palette->clips[c].markers)
      state->markers.add(ClipMarker{c, m.time_seconds, m.name});
  desc_ = d;
  state_ = std::move(state);  // The old state, if any, detaches its views.
  state_->owner = this;
  detail::ViewState& own = *state_->own_view.state_;
  own.crowd = state_.get();
  own.lane = 0;  // The store's first lane, made by reset().
  own.desc = CrowdViewDesc();
  own.desc.previous_records = d.previous_records;
  detail::resetSelection(d, &own);
  state_->views.push_back(&own);
  return Status::ok();
}

// ---- Instances: validated and applied by the store ------------------------------------------

Status CrowdManager::add(const InstanceDesc& d, InstanceHandle* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "CrowdManager::add: out is null"};
  if (!state_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  Status s = state_->store.validate(d);
  if (!s.isOk()) return s;
  InstanceHandle h;
  s = state_->store.handles.allocate(&h);
  if (!s.isOk()) return s;
  state_->store.push(d, h, state_->clock);
  *out = h;
  return Status::ok();
}

Status CrowdManager::addRandom(const RandomCrowdDesc& r, std::vector<InstanceHandle>* out) {
  if (!state_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  detail::InstanceStore& store = state_->store;
  const BakedPalette& palette = *desc_.palette;
  if (!(r.optional_probability >= 0.0f && r.optional_probability <= 1.0f) ||
      !(r.min_speed >= 0.0f && r.max_speed >= r.min_speed) || !std::isfinite(r.max_speed))
    return {StatusCode::kInvalidArgument,
            "RandomCrowdDesc: probability must be in [0, 1] and 0 <= min_speed <= max_speed"};
  for (uint32_t c : r.clips)
    if (c >= palette.clips.size())
      return {StatusCode::kInvalidArgument, strCat("RandomCrowdDesc.clips: clip ", c, " out of range")};
  if (size_t(size()) + r.positions.size() > HandlePool::kMaxSlots)
    return {StatusCode::kLimitExceeded, "RandomCrowdDesc: too many instances"};
  // Build every desc first so that a failure adds nothing.
  std::mt19937_64 rng(r.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<InstanceDesc> descs(r.positions.size());
  const uint32_t clip_count = r.clips.empty() ? uint32_t(palette.clips.size())
                                              : uint32_t(r.clips.size());
  for (size_t i = 0; i < descs.size(); ++i) {
    InstanceDesc& d = descs[i];
    d.position = r.positions[i];
    uint32_t mask = r.required_mask;
    for (uint32_t s = 0; s < 32; ++s)
      if ((r.optional_mask >> s) & 1u)
        if (unit(rng) < r.optional_probability) mask |= 1u << s;
    d.variation_mask = mask;
    const uint32_t pick = std::min(clip_count - 1, uint32_t(unit(rng) * clip_count));
    d.clip = r.clips.empty() ? pick : r.clips[pick];
    d.time_seconds = r.random_time ? unit(rng) * palette.clips[d.clip].duration_seconds : 0.0;
    if (r.random_heading) {
      const double a = unit(rng) * 6.283185307179586;
      d.rotation = glm::quat(float(std::cos(a / 2)), 0.0f, float(std::sin(a / 2)), 0.0f);
    }
    d.speed = float(r.min_speed + (r.max_speed - r.min_speed) * unit(rng));
    d.root_motion = r.root_motion;
    const uint32_t hue = uint32_t(unit(rng) * 0xFFFFFF);
    d.color = glm::u8vec4(hue & 0xFF, (hue >> 8) & 0xFF, (hue >> 16) & 0xFF, 255);
    Status s = store.validate(d);
    if (!s.isOk()) return {s.code(), strCat("RandomCrowdDesc instance ", i, ": ", s.message())};
  }
  for (const InstanceDesc& d : descs) {
    InstanceHandle h;
    Status s = store.handles.allocate(&h);
    if (!s.isOk()) return s;  // Unreachable: capacity checked above.
    store.push(d, h, state_->clock);
    if (out != nullptr) out->push_back(h);
  }
  return Status::ok();
}

Status CrowdManager::noCrowd() {
  return {StatusCode::kNotFound, "CrowdManager: init() first (no instances)"};
}

bool CrowdManager::contains(InstanceHandle h) const {
  return state_ && state_->store.handles.state(h) == HandleState::kAlive;
}
Status CrowdManager::remove(InstanceHandle h) { return state_ ? state_->store.remove(h) : noCrowd(); }
uint32_t CrowdManager::size() const { return state_ ? state_->store.size() : 0; }

Status CrowdManager::setTransform(InstanceHandle h, const glm::dvec3& position,
                                  const glm::quat& rotation, float scale) {
  return state_ ? state_->store.setTransform(h, position, rotation, scale, state_->clock)
                : noCrowd();
}
Status CrowdManager::setRootMotion(InstanceHandle h, bool enabled) {
  return state_ ? state_->store.setRootMotion(h, enabled, state_->clock) : noCrowd();
}
Status CrowdManager::setColor(InstanceHandle h, glm::u8vec4 color) {
  return state_ ? state_->store.setColor(h, color) : noCrowd();
}
Status CrowdManager::setCustomLayer(InstanceHandle h, uint8_t custom_layer) {
  return state_ ? state_->store.setCustomLayer(h, custom_layer) : noCrowd();
}
Status CrowdManager::setVariationMask(InstanceHandle h, uint32_t mask) {
  return state_ ? state_->store.setVariationMask(h, mask) : noCrowd();
}
Status CrowdManager::play(InstanceHandle h, uint32_t clip, double time_seconds, float speed) {
  return state_ ? state_->store.play(h, clip, time_seconds, speed, state_->clock) : noCrowd();
}
Status CrowdManager::crossfade(InstanceHandle h, uint32_t clip, double blend_seconds,
                               double time_seconds) {
  return state_ ? state_->store.crossfade(h, clip, blend_seconds, time_seconds, state_->clock)
                : noCrowd();
}

Status CrowdManager::get(InstanceHandle h, InstanceDesc* out) const {
  uint32_t i = 0;
  const Status s = state_ ? state_->store.denseIndexFor(h, out, "get", &i) : noCrowd();
  if (!s.isOk()) return s;
  const detail::InstanceStore& st = state_->store;
  InstanceDesc d;
  d.position = st.positions.get(i);
  d.rotation = st.rotations.get(i);
  d.scale = st.scales[i];
  d.color = detail::appearanceColor(st.colors[i]);
  d.custom_layer = uint8_t(st.colors[i] >> 24);
  d.variation_mask = st.masks[i];
  d.clip = st.playback[i].clip;
  d.time_seconds = detail::localTime(st.playback[i], state_->clips[d.clip], state_->clock);
  d.speed = st.playback[i].speed;
  d.loop_mode = st.playback[i].loop;
  d.root_motion = st.root_motion[i] != 0;
  *out = d;
  return Status::ok();
}

// ---- The frame ------------------------------------------------------------------------------

Status CrowdManager::update(double dt, const Camera& camera, const ParallelFor& parallel_for) {
  Status advanced = advanceClock(dt);  // Checks init() and dt.
  if (!advanced.isOk()) return advanced;
  ParallelFor own;
  detail::FrameInputs in =
      detail::frameInputs(*state_, *state_->own_view.state_, camera,
                          detail::taskRunner(*state_, parallel_for, &own), true);
  // Instances moved by their root motion: the exported state changes, each moved one stamped
  // with this version (from parallel tasks, without the change log).
  if (in.root_motion && dt > 0.0) state_->store.unloggedVersion();
  detail::selectView(in, camera, state_->own_view.state_.get());
  detail::gatherEvents(state_.get());
  return Status::ok();
}

Status CrowdManager::advance(double dt, const ParallelFor& parallel_for) {
  Status advanced = advanceClock(dt);  // Checks init() and dt.
  if (!advanced.isOk()) return advanced;
  // Nothing to simulate per instance: no root motion, no markers (a crossfade's end is read
  // from the clock where it matters, not written here).
  if (state_->store.root_motion_count == 0 && state_->markers.empty()) {
    state_->events.clear();
    return Status::ok();
  }
  ParallelFor own;
  detail::FrameInputs in =
      detail::frameInputs(*state_, *state_->own_view.state_, Camera(),
                          detail::taskRunner(*state_, parallel_for, &own), true);
  if (in.root_motion && dt > 0.0) state_->store.unloggedVersion();
  detail::simulateFrame(in, state_->store);
  detail::gatherEvents(state_.get());
  return Status::ok();
}

const CrowdView& CrowdManager::view() const {
  static const CrowdView empty;
  return state_ ? state_->own_view : empty;
}

Status CrowdManager::advanceClock(double dt) {  // The step both update() and advance() take.
  if (!state_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  if (!std::isfinite(dt) || dt < 0.0)
    return {StatusCode::kInvalidArgument, "dt_seconds must be finite and >= 0"};
  detail::CrowdState& s = *state_;
  if (!std::isfinite(s.clock + dt))
    return {StatusCode::kInvalidArgument, "dt_seconds would take the crowd clock past a double"};
  ++s.steps;
  // A held clock stays bitwise where it is: the compensation alone (up to half an ulp) could
  // round it one ulp on, and nothing would be stamped for what that moved.
  if (dt == 0.0) return Status::ok();
  // Compensated (Kahan) sum: after a week of 60 Hz frames the clock is still within a few
  // ulps of the exact sum.
  const double y = dt - s.clock_compensation;
  const double t = s.clock + y;
  s.clock_compensation = (t - s.clock) - y;
  s.clock = t;
  s.store.releaseFadedLivePoses(t);  // Hand-overs back to the clip that are over.
  return Status::ok();
}

double CrowdManager::clockSeconds() const {
  return state_ ? state_->clock : 0.0;
}
Status CrowdManager::addClipMarker(uint32_t clip, double time_seconds, const std::string& name,
                                   uint32_t* index) {
  if (!state_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  if (clip >= state_->clips.size())
    return {StatusCode::kInvalidArgument, strCat("addClipMarker: clip ", clip, " out of range")};
  const double duration = state_->clips[clip].duration;
  if (!std::isfinite(time_seconds) || time_seconds < 0.0 || time_seconds > duration)
    return {StatusCode::kInvalidArgument,
            strCat("addClipMarker: time ", time_seconds, " is outside the clip's [0, ", duration,
                   "] seconds")};
  detail::MarkerTable& t = state_->markers;
  // Until now nothing was tracked: every instance counts from the current clock.
  if (t.empty()) state_->store.markEventsReported(state_->clock);
  const uint32_t added = t.add(ClipMarker{clip, time_seconds, name});
  if (index != nullptr) *index = added;
  return Status::ok();
}

const std::vector<ClipMarker>& CrowdManager::clipMarkers() const {
  return (state_ ? *state_ : emptyState()).markers.markers;
}

Span<const AnimationEvent> CrowdManager::events() const {
  return (state_ ? *state_ : emptyState()).events;
}

uint64_t CrowdManager::identity() const { return state_ ? state_->store.identity : 0; }
uint64_t CrowdManager::stepCount() const {
  return state_ ? state_->steps : 0;
}

Status CrowdManager::setLodMode(LodMode mode, float pixel_error_budget) {
  if (!state_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  const float budget = pixel_error_budget == 0.0f ? 1.0f : pixel_error_budget;
  Status s = checkLodMode(mode, budget, desc_.lod_count, desc_.lod_errors_units);
  if (!s.isOk()) return s;
  desc_.lod_mode = mode;
  desc_.pixel_error_budget = budget;
  state_->store.version = detail::nextStateVersion();
  return Status::ok();
}

Status CrowdManager::setLodDistances(Span<const float> lines, float max_distance_radii) {
  if (!state_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  const float far_line = max_distance_radii == 0.0f ? desc_.max_distance_radii : max_distance_radii;
  Status s = checkLodLines(desc_.lod_count, lines, far_line);
  if (!s.isOk()) return s;
  desc_.lod_distances_radii.assign(lines.begin(), lines.end());
  desc_.max_distance_radii = far_line;
  state_->lod_lines = desc_.lod_distances_radii;
  state_->store.version = detail::nextStateVersion();
  return Status::ok();
}

}  // namespace si
