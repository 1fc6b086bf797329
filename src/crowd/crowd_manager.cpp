// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Instance state, playback, LOD with hysteresis, frustum culling and bucketing. The per-frame
// loop follows B. Dudash, "Skinned Instancing" (NVIDIA, 2007): LOD lists per frame on the CPU,
// frustum culling before anything reaches the GPU.
#include "si/crowd/crowd_manager.h"

#include "crowd/cull_math.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <random>

#include "core/str_cat.h"

namespace si {
using detail::strCat;

namespace {
constexpr uint32_t kMaxLods = 8;

uint32_t packColor(glm::u8vec4 c) {
  return uint32_t(c.r) | (uint32_t(c.g) << 8) | (uint32_t(c.b) << 16) | (uint32_t(c.a) << 24);
}
glm::u8vec4 unpackColor(uint32_t c) {
  return glm::u8vec4(c & 0xFF, (c >> 8) & 0xFF, (c >> 16) & 0xFF, c >> 24);
}
uint32_t floatBits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
bool finite3(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
// State versions are unique across every CrowdManager of the process, so a consumer keyed on
// (address, version) never mistakes a new crowd at a reused address for the old one.
uint64_t nextStateVersion() {
  static std::atomic<uint64_t> counter{0};
  return ++counter;
}

}  // namespace

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
  return d;
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
  if (d.sub_mesh_count < 1 || d.sub_mesh_count > 32)
    return {StatusCode::kInvalidArgument, "CrowdDesc.sub_mesh_count must be 1 to 32"};
  if (d.lod_count > kMaxLods)
    return {StatusCode::kInvalidArgument, "CrowdDesc.lod_count must be at most 8"};
  if (!std::isfinite(d.character_radius) || d.character_radius <= 0.0f)
    return {StatusCode::kInvalidArgument, "CrowdDesc.character_radius must be finite and > 0"};
  s = checkLodLines(d.lod_count, d.lod_distances_radii, d.max_distance_radii);
  if (!s.isOk()) return s;
  if (!std::isfinite(d.lod_hysteresis_ratio) ||
      d.lod_hysteresis_ratio < 0.0f || d.lod_hysteresis_ratio >= 1.0f)
    return {StatusCode::kInvalidArgument,
            "CrowdDesc.max_distance_radii must be finite; lod_hysteresis_ratio in [0, 1)"};
  if (!std::isfinite(d.animation_lod_rate_hz) || d.animation_lod_rate_hz <= 0.0f)
    return {StatusCode::kInvalidArgument, "CrowdDesc.animation_lod_rate_hz must be > 0"};
  *this = CrowdManager();
  state_version_ = nextStateVersion();
  desc_ = d;
  radius_ = d.character_radius;
  lod_lines_ = d.lod_distances_radii;
  initialized_ = true;
  bucket_offsets_.assign(bucketCount() + 1, 0);
  for (const BakedClip& c : d.palette->clips) {
    ClipInfo info;
    info.duration = c.duration_seconds;
    info.inv_duration = c.duration_seconds > 0.0f ? 1.0 / c.duration_seconds : 0.0;
    info.interval = c.frame_interval_seconds;
    info.inv_interval = c.frame_interval_seconds > 0.0 ? 1.0 / c.frame_interval_seconds : 0.0;
    info.first_texel = c.first_texel;
    info.last_interval = c.frame_count >= 2 ? c.frame_count - 2 : 0;
    info.uniform = c.frame_times_seconds.empty() && c.frame_count >= 2 && info.interval > 0.0;
    info.sphere_center = c.bounding_sphere.center;
    info.sphere_radius = c.bounding_sphere.radius;
    clip_info_.push_back(info);
  }
  return Status::ok();
}

Status CrowdManager::validateInstance(const InstanceDesc& d) const {
  if (!initialized_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  if (d.clip >= desc_.palette->clips.size())
    return {StatusCode::kInvalidArgument,
            strCat("InstanceDesc.clip ", d.clip, " is not below the palette's ",
                   desc_.palette->clips.size(), " clips")};
  if (!finite3(d.position)) return {StatusCode::kInvalidArgument, "InstanceDesc.position is not finite"};
  if (!isFinite(d.rotation) || glm::dot(d.rotation, d.rotation) == 0.0f)
    return {StatusCode::kInvalidArgument, "InstanceDesc.rotation must be finite and non-zero"};
  if (!std::isfinite(d.scale) || d.scale <= 0.0f)
    return {StatusCode::kInvalidArgument, "InstanceDesc.scale must be finite and > 0"};
  if (!std::isfinite(d.time_seconds))
    return {StatusCode::kInvalidArgument, "InstanceDesc.time_seconds is not finite"};
  if (!std::isfinite(d.speed) || d.speed < 0.0f)
    return {StatusCode::kInvalidArgument, "InstanceDesc.speed must be finite and >= 0"};
  if (d.loop_mode != LoopMode::kDefault && d.loop_mode != LoopMode::kOnce &&
      d.loop_mode != LoopMode::kLoop)
    return {StatusCode::kInvalidArgument, "InstanceDesc.loop_mode is unknown"};
  return Status::ok();
}

void CrowdManager::pushInstance(const InstanceDesc& d, InstanceHandle h) {
  uint32_t slot = 0;
  (void)handles_.slot(h, &slot);  // Just issued: alive.
  if (slot_to_dense_.size() <= slot) slot_to_dense_.resize(slot + 1, 0);
  slot_to_dense_[slot] = static_cast<uint32_t>(positions_.size());
  positions_.push_back(d.position);
  rotations_.push_back(glm::normalize(d.rotation));
  scales_.push_back(d.scale);
  colors_.push_back(packColor(d.color));
  masks_.push_back(d.variation_mask);
  const LoopMode loop = d.loop_mode == LoopMode::kDefault
                            ? desc_.palette->clips[d.clip].loop_mode : d.loop_mode;
  playback_.push_back(Playback{d.clip, loop, d.speed, clock_, d.time_seconds});
  fade_from_.push_back(playback_.back());
  fade_start_.push_back(0.0);
  fade_duration_.push_back(0.0);
  lods_.push_back(0);
  dense_handles_.push_back(h);
  state_version_ = nextStateVersion();
}

Status CrowdManager::add(const InstanceDesc& d, InstanceHandle* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "CrowdManager::add: out is null"};
  Status s = validateInstance(d);
  if (!s.isOk()) return s;
  InstanceHandle h;
  s = handles_.allocate(&h);
  if (!s.isOk()) return s;
  pushInstance(d, h);
  *out = h;
  return Status::ok();
}

Status CrowdManager::addRandom(const RandomCrowdDesc& r, std::vector<InstanceHandle>* out) {
  if (!initialized_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  if (!(r.optional_probability >= 0.0f && r.optional_probability <= 1.0f) ||
      !(r.min_speed >= 0.0f && r.max_speed >= r.min_speed) || !std::isfinite(r.max_speed))
    return {StatusCode::kInvalidArgument,
            "RandomCrowdDesc: probability must be in [0, 1] and 0 <= min_speed <= max_speed"};
  for (uint32_t c : r.clips)
    if (c >= desc_.palette->clips.size())
      return {StatusCode::kInvalidArgument, strCat("RandomCrowdDesc.clips: clip ", c, " out of range")};
  if (size_t(size()) + r.positions.size() > HandlePool::kMaxSlots)
    return {StatusCode::kLimitExceeded, "RandomCrowdDesc: too many instances"};
  // Build every desc first so that a failure adds nothing.
  std::mt19937_64 rng(r.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<InstanceDesc> descs(r.positions.size());
  const uint32_t clip_count = r.clips.empty() ? uint32_t(desc_.palette->clips.size())
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
    d.time_seconds = r.random_time ? unit(rng) * desc_.palette->clips[d.clip].duration_seconds : 0.0;
    if (r.random_heading) {
      const double a = unit(rng) * 6.283185307179586;
      d.rotation = glm::quat(float(std::cos(a / 2)), 0.0f, float(std::sin(a / 2)), 0.0f);
    }
    d.speed = float(r.min_speed + (r.max_speed - r.min_speed) * unit(rng));
    const uint32_t hue = uint32_t(unit(rng) * 0xFFFFFF);
    d.color = glm::u8vec4(hue & 0xFF, (hue >> 8) & 0xFF, (hue >> 16) & 0xFF, 255);
    Status s = validateInstance(d);
    if (!s.isOk()) return {s.code(), strCat("RandomCrowdDesc instance ", i, ": ", s.message())};
  }
  for (const InstanceDesc& d : descs) {
    InstanceHandle h;
    Status s = handles_.allocate(&h);
    if (!s.isOk()) return s;  // Unreachable: capacity checked above.
    pushInstance(d, h);
    if (out != nullptr) out->push_back(h);
  }
  return Status::ok();
}

Status CrowdManager::denseIndex(InstanceHandle h, uint32_t* dense) const {
  uint32_t slot = 0;
  Status s = handles_.slot(h, &slot);
  if (!s.isOk()) return s;
  *dense = slot_to_dense_[slot];
  return Status::ok();
}

bool CrowdManager::contains(InstanceHandle h) const {
  return handles_.state(h) == HandleState::kAlive;
}

Status CrowdManager::remove(InstanceHandle h) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  const uint32_t last = size() - 1;
  const auto move_last = [&](auto& v) {
    v[i] = v[last];
    v.pop_back();
  };
  if (i != last) {
    uint32_t moved_slot = 0;
    (void)handles_.slot(dense_handles_[last], &moved_slot);
    slot_to_dense_[moved_slot] = i;
  }
  move_last(positions_);
  move_last(rotations_);
  move_last(scales_);
  move_last(colors_);
  move_last(masks_);
  move_last(playback_);
  move_last(fade_from_);
  move_last(fade_start_);
  move_last(fade_duration_);
  move_last(lods_);
  move_last(dense_handles_);
  state_version_ = nextStateVersion();
  return handles_.release(h);
}

Status CrowdManager::setTransform(InstanceHandle h, const glm::dvec3& position,
                                  const glm::quat& rotation, float scale) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  if (!finite3(position) || !isFinite(rotation) || glm::dot(rotation, rotation) == 0.0f ||
      !std::isfinite(scale) || scale <= 0.0f)
    return {StatusCode::kInvalidArgument,
            "setTransform: position, rotation must be finite, rotation non-zero, scale > 0"};
  positions_[i] = position;
  rotations_[i] = glm::normalize(rotation);
  scales_[i] = scale;
  state_version_ = nextStateVersion();
  return Status::ok();
}

Status CrowdManager::setColor(InstanceHandle h, glm::u8vec4 color) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (s.isOk()) colors_[i] = packColor(color), state_version_ = nextStateVersion();
  return s;
}

Status CrowdManager::setVariationMask(InstanceHandle h, uint32_t mask) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (s.isOk()) masks_[i] = mask, state_version_ = nextStateVersion();
  return s;
}

Status CrowdManager::play(InstanceHandle h, uint32_t clip, double time_seconds, float speed) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  if (clip >= desc_.palette->clips.size() || !std::isfinite(time_seconds) ||
      !std::isfinite(speed) || speed < 0.0f)
    return {StatusCode::kInvalidArgument,
            "play: clip must be in range, time finite, speed finite and >= 0"};
  playback_[i] = Playback{clip, desc_.palette->clips[clip].loop_mode, speed, clock_, time_seconds};
  fade_duration_[i] = 0.0;
  state_version_ = nextStateVersion();
  return Status::ok();
}

Status CrowdManager::crossfade(InstanceHandle h, uint32_t clip, double blend_seconds,
                               double time_seconds) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  if (clip >= desc_.palette->clips.size() || !std::isfinite(blend_seconds) ||
      blend_seconds <= 0.0 || !std::isfinite(time_seconds))
    return {StatusCode::kInvalidArgument,
            "crossfade: clip must be in range, blend_seconds finite and > 0, time finite"};
  fade_from_[i] = playback_[i];
  fade_start_[i] = clock_;
  fade_duration_[i] = blend_seconds;
  playback_[i] = Playback{clip, desc_.palette->clips[clip].loop_mode, playback_[i].speed, clock_,
                          time_seconds};
  state_version_ = nextStateVersion();
  return Status::ok();
}

FrameSample CrowdManager::fastSample(uint32_t clip, double t) const {
  const ClipInfo& c = clip_info_[clip];
  if (!c.uniform) return sampleFrames(desc_.palette->clips[clip], t);
  // si::sampleFrames' uniform-grid path with a reciprocal instead of a division; t is already
  // within [0, duration].
  const double position = t * c.inv_interval;
  const uint32_t i = std::min(static_cast<uint32_t>(position), c.last_interval);
  FrameSample s;
  s.frame = i;
  s.next_frame = i + 1;
  s.fraction = static_cast<float>(std::min(std::max(position - double(i), 0.0), 1.0));
  return s;
}

double CrowdManager::localTime(const Playback& p, double clock) const {
  const ClipInfo& c = clip_info_[p.clip];
  const double duration = c.duration;
  // Derived from the crowd clock, never accumulated per instance: no drift over long runs.
  const double t = p.start_time + (clock - p.start_clock) * double(p.speed);
  if (!(duration > 0.0)) return 0.0;
  if (p.loop == LoopMode::kLoop) {
    // t - floor(t / d) * d: the same as fmod for these magnitudes, and several times cheaper.
    double w = t - std::floor(t * c.inv_duration) * duration;
    if (w < 0.0) w += duration;
    return w >= duration ? 0.0 : w;
  }
  return std::clamp(t, 0.0, duration);
}

Status CrowdManager::get(InstanceHandle h, InstanceDesc* out) const {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  if (out == nullptr) return {StatusCode::kInvalidArgument, "get: out is null"};
  InstanceDesc d;
  d.position = positions_[i];
  d.rotation = rotations_[i];
  d.scale = scales_[i];
  d.color = unpackColor(colors_[i]);
  d.variation_mask = masks_[i];
  d.clip = playback_[i].clip;
  d.time_seconds = localTime(playback_[i], clock_);
  d.speed = playback_[i].speed;
  d.loop_mode = playback_[i].loop;
  *out = d;
  return Status::ok();
}

Status CrowdManager::lodOf(InstanceHandle h, uint32_t* lod) const {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (s.isOk() && lod != nullptr) *lod = lods_[i];
  return s;
}

FrameSample CrowdManager::frameSample(uint32_t clip, double local_time_seconds) const {
  return fastSample(clip, std::min(std::max(local_time_seconds, 0.0), clip_info_[clip].duration));
}

Status CrowdManager::update(double dt, const Camera& camera) {
  Status advanced = advanceClock(dt);  // Checks init() and dt.
  if (!advanced.isOk()) return advanced;

  const BakedPalette& palette = *desc_.palette;
  const uint32_t n = size(), submeshes = desc_.sub_mesh_count;
  const cull::Params cull_params = cullParams(camera);
  const double anim_step = cull_params.animation_step_seconds;
  const uint32_t anim_lod = cull_params.animation_lod_start;

  stats_ = CrowdFrameStats();
  stats_.instances = n;
  visible_dense_.clear();
  records_.clear();
  visible_handles_.clear();
  std::fill(bucket_offsets_.begin(), bucket_offsets_.end(), 0u);

  // Pass 1: distance, LOD, culling, records; count bucket entries. The selection uses only
  // +, -, * and comparisons in a fixed order (cull_math.h), so the GPU-driven culling pass,
  // which does the same arithmetic, selects exactly the same instances and LODs.
  for (uint32_t i = 0; i < n; ++i) {
    const glm::vec3 rel(positions_[i] - camera.position);  // Camera-relative, from double.
    const Playback& pb = playback_[i];
    // A crossfade is over once the clock passes its end (compared without a division).
    if (fade_duration_[i] > 0.0 && !(clock_ - fade_start_[i] < fade_duration_[i]))
      fade_duration_[i] = 0.0;
    const bool fading = fade_duration_[i] > 0.0;
    const ClipInfo& ca = clip_info_[pb.clip];
    const ClipInfo& cb = clip_info_[fading ? fade_from_[i].clip : pb.clip];
    cull::Selection sel;
    sel.lod = lods_[i];
    if (!cull::select(rel, rotations_[i], scales_[i], ca.sphere_center, ca.sphere_radius,
                      cb.sphere_center, cb.sphere_radius, cull_params, &sel)) {
      ++(sel.culled_by_distance ? stats_.culled_distance : stats_.culled_frustum);
      continue;
    }
    const uint32_t lod = sel.lod;
    lods_[i] = static_cast<uint8_t>(lod);
    ++stats_.per_lod[lod];
    const glm::quat& q = rotations_[i];
    const float s = scales_[i];

    // The record.
    InstanceRecord rec;
    const glm::mat3 r = glm::mat3_cast(q) * s;
    for (int row = 0; row < 3; ++row) {
      rec.world_rows[row][0] = r[0][row];
      rec.world_rows[row][1] = r[1][row];
      rec.world_rows[row][2] = r[2][row];
      rec.world_rows[row][3] = rel[row];
    }
    double ta = localTime(pb, clock_);
    if (lod >= anim_lod) ta = std::floor(ta / anim_step) * anim_step;
    const FrameSample fa = fastSample(pb.clip, ta);
    const uint32_t stride = palette.layout.frame_stride_texels;
    rec.frames[0] = ca.first_texel + fa.frame * stride;
    rec.frames[1] = ca.first_texel + fa.next_frame * stride;
    rec.blend[0] = floatBits(fa.fraction);
    rec.blend[3] = colors_[i];
    float weight_b = 0.0f;
    if (fading) weight_b = std::min(float((clock_ - fade_start_[i]) / fade_duration_[i]), 1.0f);
    if (fading) {
      // Clip A is the one fading out; B the new one, weighted by weight_b.
      const Playback& old = fade_from_[i];
      double tb = localTime(old, clock_);
      if (lod >= anim_lod) tb = std::floor(tb / anim_step) * anim_step;
      const ClipInfo& co = clip_info_[old.clip];
      const FrameSample fo = fastSample(old.clip, tb);
      rec.frames[2] = rec.frames[0];
      rec.frames[3] = rec.frames[1];
      rec.blend[1] = rec.blend[0];
      rec.frames[0] = co.first_texel + fo.frame * stride;
      rec.frames[1] = co.first_texel + fo.next_frame * stride;
      rec.blend[0] = floatBits(fo.fraction);
      rec.blend[2] = floatBits(std::max(0.0f, weight_b));
    } else {
      rec.frames[2] = rec.frames[0];
      rec.frames[3] = rec.frames[1];
      rec.blend[1] = rec.blend[0];
      rec.blend[2] = floatBits(0.0f);
    }
    records_.push_back(rec);
    visible_dense_.push_back(i);
    visible_handles_.push_back(dense_handles_[i]);
    uint32_t mask = masks_[i] & (submeshes == 32 ? 0xFFFFFFFFu : ((1u << submeshes) - 1u));
    while (mask) {
      const uint32_t sm = uint32_t(__builtin_ctz(mask));
      mask &= mask - 1;
      ++bucket_offsets_[lod * submeshes + sm + 1];
    }
  }
  stats_.visible = static_cast<uint32_t>(records_.size());

  // Prefix sums, then pass 2: fill each bucket in visible order (deterministic).
  const uint32_t buckets = bucketCount();
  for (uint32_t b = 0; b < buckets; ++b) bucket_offsets_[b + 1] += bucket_offsets_[b];
  stats_.bucket_entries = bucket_offsets_[buckets];
  bucket_entries_.resize(stats_.bucket_entries);
  bucket_cursor_.assign(bucket_offsets_.begin(), bucket_offsets_.end() - 1);
  for (uint32_t v = 0; v < visible_dense_.size(); ++v) {
    const uint32_t i = visible_dense_[v];
    const uint32_t base = lods_[i] * submeshes;
    uint32_t mask = masks_[i] & (submeshes == 32 ? 0xFFFFFFFFu : ((1u << submeshes) - 1u));
    while (mask) {
      const uint32_t sm = uint32_t(__builtin_ctz(mask));
      mask &= mask - 1;
      bucket_entries_[bucket_cursor_[base + sm]++] = v;
    }
  }
  return Status::ok();
}

CullParams CrowdManager::cullParams(const Camera& camera) const {
  CullParams p;
  p.planes = camera.frustumPlanes();
  p.radius = radius_;
  p.max_distance_radii = desc_.max_distance_radii;
  p.hysteresis = desc_.lod_hysteresis_ratio;
  p.lod_count = desc_.lod_count;
  for (size_t l = 0; l < lod_lines_.size() && l < 7; ++l) p.lod_lines[l] = lod_lines_[l];
  p.animation_lod_start = desc_.animation_lod_start == 0 ? kMaxLods : desc_.animation_lod_start;
  p.animation_step_seconds = 1.0 / double(desc_.animation_lod_rate_hz);
  return p;
}

Status CrowdManager::advanceClock(double dt) {
  if (!initialized_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  if (!std::isfinite(dt) || dt < 0.0)
    return {StatusCode::kInvalidArgument, "dt_seconds must be finite and >= 0"};
  // Compensated (Kahan) sum: after a week of 60 Hz frames the clock is still within a few
  // ulps of the exact sum.
  const double y = dt - clock_compensation_;
  const double t = clock_ + y;
  clock_compensation_ = (t - clock_) - y;
  clock_ = t;
  return Status::ok();
}

void CrowdManager::exportGpuState(std::vector<GpuInstanceState>* out,
                                  std::vector<InstanceHandle>* handles) const {
  const uint32_t n = size();
  out->resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    GpuInstanceState& g = (*out)[i];
    g = GpuInstanceState{};
    for (int k = 0; k < 3; ++k) g.position[k] = positions_[i][k];
    const glm::quat& q = rotations_[i];
    g.rotation[0] = q.x, g.rotation[1] = q.y, g.rotation[2] = q.z, g.rotation[3] = q.w;
    g.scale = scales_[i];
    g.color = colors_[i];
    g.variation_mask = masks_[i];
    g.lod = lods_[i];
    const Playback& a = playback_[i];
    g.start_clock = a.start_clock;
    g.start_time = a.start_time;
    g.clip = a.clip;
    g.loop = uint32_t(a.loop);
    g.speed = a.speed;
    g.fading = fade_duration_[i] > 0.0 ? 1u : 0u;
    g.fade_start = fade_start_[i];
    g.fade_duration = fade_duration_[i];
    const Playback& b = fade_from_[i];
    g.from_start_clock = b.start_clock;
    g.from_start_time = b.start_time;
    g.from_clip = b.clip;
    g.from_loop = uint32_t(b.loop);
    g.from_speed = b.speed;
  }
  if (handles != nullptr) *handles = dense_handles_;
}

void CrowdManager::exportGpuClips(std::vector<GpuClipInfo>* clips,
                                  std::vector<double>* frame_times) const {
  clips->clear();
  frame_times->clear();
  for (size_t c = 0; c < clip_info_.size(); ++c) {
    const ClipInfo& ci = clip_info_[c];
    const BakedClip& bc = desc_.palette->clips[c];
    GpuClipInfo g{};
    g.duration = ci.duration;
    g.inv_duration = ci.inv_duration;
    g.interval = ci.interval;
    g.inv_interval = ci.inv_interval;
    g.sphere[0] = ci.sphere_center.x, g.sphere[1] = ci.sphere_center.y;
    g.sphere[2] = ci.sphere_center.z, g.sphere[3] = ci.sphere_radius;
    g.first_texel = ci.first_texel;
    g.last_interval = ci.last_interval;
    g.uniform_grid = ci.uniform ? 1u : 0u;
    g.frame_count = bc.frame_count;
    g.times_offset = uint32_t(frame_times->size());
    frame_times->insert(frame_times->end(), bc.frame_times_seconds.begin(),
                        bc.frame_times_seconds.end());
    clips->push_back(g);
  }
}

Status CrowdManager::setLodDistances(Span<const float> lines, float max_distance_radii) {
  if (!initialized_) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  const float far_line = max_distance_radii == 0.0f ? desc_.max_distance_radii : max_distance_radii;
  Status s = checkLodLines(desc_.lod_count, lines, far_line);
  if (!s.isOk()) return s;
  desc_.lod_distances_radii.assign(lines.begin(), lines.end());
  desc_.max_distance_radii = far_line;
  lod_lines_ = desc_.lod_distances_radii;
  state_version_ = nextStateVersion();
  return Status::ok();
}

Status CrowdManager::jointMatrix(InstanceHandle h, uint32_t joint, glm::dmat4* out) const {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  if (out == nullptr) return {StatusCode::kInvalidArgument, "jointMatrix: out is null"};
  const BakedPalette& p = *desc_.palette;
  if (joint >= p.skeleton_to_palette.size() || p.skeleton_to_palette[joint] < 0)
    return {StatusCode::kOutOfRange, strCat("jointMatrix: joint ", joint, " is not in the palette")};
  const uint32_t slot = uint32_t(p.skeleton_to_palette[joint]);
  const Playback& pb = playback_[i];
  glm::mat4 m = emulateSkinningMatrix(p, pb.clip, sampleFrames(p.clips[pb.clip], localTime(pb, clock_)), slot);
  if (fade_duration_[i] > 0.0) {
    const float w = float(std::clamp((clock_ - fade_start_[i]) / fade_duration_[i], 0.0, 1.0));
    const Playback& old = fade_from_[i];
    const glm::mat4 mo = emulateSkinningMatrix(
        p, old.clip, sampleFrames(p.clips[old.clip], localTime(old, clock_)), slot);
    m = mo * (1.0f - w) + m * w;  // The shader blends the two clips' matrices the same way.
  }
  glm::dmat4 world(glm::mat3_cast(glm::dquat(rotations_[i])) * double(scales_[i]));
  world[3] = glm::dvec4(positions_[i], 1.0);
  *out = world * glm::dmat4(m);
  return Status::ok();
}

}  // namespace si
