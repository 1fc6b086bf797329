// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The crowd's instance state and its changes.
#include "crowd/instance_store.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/str_cat.h"
#include "crowd/instance_root_motion.h"

namespace si::detail {

namespace {
bool finite3(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Status validateColor(glm::u8vec4 color) {
  if (color.a == 255) return Status::ok();
  return {StatusCode::kInvalidArgument,
          strCat("the tint's alpha is ", int(color.a), ": it must be 255 (the tint is RGB; the ",
                 "record's fourth byte holds the custom texture layer: InstanceDesc::custom_layer)")};
}
}  // namespace

uint64_t nextStateVersion() {
  static std::atomic<uint64_t> counter{0};
  return ++counter;
}

void InstanceStore::reset(const BakedPalette* p) {
  *this = InstanceStore();
  palette = p;
  views.resize(1);
  views[0].used = true;
  version = nextStateVersion();
  identity = version;
  change_log.restart(version);
}

uint32_t InstanceStore::addView() {
  uint32_t lane = 0;
  while (lane < views.size() && views[lane].used) ++lane;
  if (lane == views.size()) views.emplace_back();
  ViewLanes& v = views[lane];
  v.used = true;
  v.lods.assign(size(), 0);
  v.record_slot.assign(size(), kNoPreviousRecord);
  v.previous_slot.assign(size(), kNoPreviousRecord);
  return lane;
}

void InstanceStore::changed(uint32_t i, bool placed) {
  version = nextStateVersion();
  stamp(i, placed);
  // Up to an eighth of the instances: past that a consumer scans the stamps about as fast.
  change_log.add(version, i, placed, std::max<size_t>(4096, size() / 8));
  pending.set(i, placed);
}

void InstanceStore::unloggedVersion() {
  version = nextStateVersion();
  change_log.restart(version);
  pending.invalidate();
}

void InstanceStore::stamp(uint32_t i, bool placed) {
  const uint32_t chunk = i / kStampChunk;
  changed_at[i] = version;
  chunk_changed_at[chunk] = version;
  if (!placed) return;
  placed_at[i] = version;
  chunk_placed_at[chunk] = version;
}

void InstanceStore::releaseView(uint32_t lane) {
  if (lane == 0 || lane >= views.size()) return;
  views[lane] = ViewLanes();  // Frees its memory; unused lanes follow no instance.
}

Status InstanceStore::validate(const InstanceDesc& d) const {
  if (palette == nullptr) return {StatusCode::kInvalidArgument, "CrowdManager: init() first"};
  if (d.clip >= palette->clips.size())
    return {StatusCode::kInvalidArgument,
            strCat("InstanceDesc.clip ", d.clip, " is not below the palette's ",
                   palette->clips.size(), " clips")};
  if (!finite3(d.position)) return {StatusCode::kInvalidArgument, "InstanceDesc.position is not finite"};
  if (!isFinite(d.rotation) || glm::dot(d.rotation, d.rotation) == 0.0f)
    return {StatusCode::kInvalidArgument, "InstanceDesc.rotation must be finite and non-zero"};
  if (!std::isfinite(d.scale) || d.scale <= 0.0f)
    return {StatusCode::kInvalidArgument, "InstanceDesc.scale must be finite and > 0"};
  if (!std::isfinite(d.time_seconds))
    return {StatusCode::kInvalidArgument, "InstanceDesc.time_seconds is not finite"};
  if (!std::isfinite(d.speed) || d.speed < 0.0f)
    return {StatusCode::kInvalidArgument, "InstanceDesc.speed must be finite and >= 0"};
  Status color = validateColor(d.color);
  if (!color.isOk()) return {color.code(), "InstanceDesc.color: " + color.message()};
  if (d.loop_mode != LoopMode::kDefault && d.loop_mode != LoopMode::kOnce &&
      d.loop_mode != LoopMode::kLoop)
    return {StatusCode::kInvalidArgument, "InstanceDesc.loop_mode is unknown"};
  return Status::ok();
}

void InstanceStore::push(const InstanceDesc& d, InstanceHandle h, double clock) {
  uint32_t slot = 0;
  (void)handles.slot(h, &slot);  // Just issued: alive.
  if (slot_to_dense.size() <= slot) slot_to_dense.resize(slot + 1, 0);
  slot_to_dense[slot] = size();
  positions.push(d.position);
  rotations.push(glm::normalize(d.rotation));
  scales.push_back(d.scale);
  colors.push_back(packAppearance(d));
  masks.push_back(d.variation_mask);
  const LoopMode loop = d.loop_mode == LoopMode::kDefault ? palette->clips[d.clip].loop_mode
                                                          : d.loop_mode;
  playback.push_back(Playback{d.clip, loop, d.speed, clock, d.time_seconds});
  fade_from.push_back(playback.back());
  fade_start.push_back(0.0);
  fade_duration.push_back(0.0);
  events_clock.push_back(clock);
  events_new.push_back(1);
  root_motion.push_back(d.root_motion ? 1 : 0);
  motion_clock.push_back(clock);
  placements.push_back(0);
  live_slot.push_back(kNoLivePose);
  root_motion_count += d.root_motion ? 1u : 0u;
  for (ViewLanes& v : views) {
    if (!v.used) continue;
    v.lods.push_back(0);
    v.record_slot.push_back(kNoPreviousRecord);
    v.previous_slot.push_back(kNoPreviousRecord);
  }
  overlays.push_back(OverlayState());
  dense_handles.push_back(h);
  changed_at.push_back(0);
  placed_at.push_back(0);
  const uint32_t chunks = (size() + kStampChunk - 1) / kStampChunk;
  if (chunk_changed_at.size() < chunks) {  // Only adds grow the store: stamps never resize.
    chunk_changed_at.resize(chunks, 0);
    chunk_placed_at.resize(chunks, 0);
  }
  pending.reserve(size());
  changed(size() - 1, true);
}

Status InstanceStore::denseIndex(InstanceHandle h, uint32_t* dense) const {
  uint32_t slot = 0;
  Status s = handles.slot(h, &slot);
  if (!s.isOk()) return s;
  *dense = slot_to_dense[slot];
  return Status::ok();
}

Status InstanceStore::denseIndexFor(InstanceHandle h, const void* out, const char* what,
                                    uint32_t* dense) const {
  const Status s = denseIndex(h, dense);
  if (s.isOk() && out == nullptr)
    return {StatusCode::kInvalidArgument, strCat(what, ": out is null")};
  return s;
}

void InstanceStore::releaseLivePose(uint32_t i) {
  if (live_slot[i] == kNoLivePose) return;
  live.release(live_slot[i]);
  live_slot[i] = kNoLivePose;
  changed(i);
}

void InstanceStore::releaseFadedLivePoses(double clock) {
  if (live.fadingOutCount() == 0) return;
  std::vector<InstanceHandle> owners;
  live.fadedOut(clock, &owners);
  for (InstanceHandle h : owners) {
    uint32_t i = 0;
    if (denseIndex(h, &i).isOk()) releaseLivePose(i);
  }
}

Status InstanceStore::remove(InstanceHandle h) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  const uint32_t last = size() - 1;
  const auto move_last = [&](auto& v) {
    v[i] = v[last];
    v.pop_back();
  };
  root_motion_count -= root_motion[i];
  if (live_slot[i] != kNoLivePose) live.release(live_slot[i]);
  overlay_count -= overlays[i].active ? 1u : 0u;
  if (i != last) {
    uint32_t moved_slot = 0;
    (void)handles.slot(dense_handles[last], &moved_slot);
    slot_to_dense[moved_slot] = i;
  }
  positions.moveLast(i);
  rotations.moveLast(i);
  move_last(scales);
  move_last(colors);
  move_last(masks);
  move_last(playback);
  move_last(fade_from);
  move_last(fade_start);
  move_last(fade_duration);
  move_last(events_clock);
  move_last(events_new);
  move_last(root_motion);
  move_last(motion_clock);
  move_last(placements);
  move_last(live_slot);
  for (ViewLanes& v : views) {
    if (!v.used) continue;
    move_last(v.lods);
    move_last(v.record_slot);
    move_last(v.previous_slot);
  }
  move_last(overlays);
  move_last(dense_handles);
  move_last(changed_at);
  move_last(placed_at);
  if (i != last)
    changed(i, true);  // The last instance moved into the hole.
  else
    version = nextStateVersion();
  return handles.release(h);
}

Status InstanceStore::setTransform(InstanceHandle h, const glm::dvec3& position,
                                   const glm::quat& rotation, float scale, double clock) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  if (!finite3(position) || !isFinite(rotation) || glm::dot(rotation, rotation) == 0.0f ||
      !std::isfinite(scale) || scale <= 0.0f)
    return {StatusCode::kInvalidArgument,
            "setTransform: position, rotation must be finite, rotation non-zero, scale > 0"};
  positions.set(i, position);
  rotations.set(i, glm::normalize(rotation));
  scales[i] = scale;
  motion_clock[i] = clock;
  ++placements[i];
  for (ViewLanes& v : views)  // A teleport: no motion vector in any view.
    if (v.used) v.record_slot[i] = kNoPreviousRecord;
  changed(i);
  return Status::ok();
}

Status InstanceStore::setRootMotion(InstanceHandle h, bool enabled, double clock) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk() || bool(root_motion[i]) == enabled) return s;
  if (enabled) {
    motion_clock[i] = clock;
    ++root_motion_count;
  } else {
    applyRootMotion(*palette, *clip_timings, clock, *this, i);
    --root_motion_count;
  }
  root_motion[i] = enabled ? 1 : 0;
  changed(i);
  return s;
}

Status InstanceStore::setColor(InstanceHandle h, glm::u8vec4 color) {
  uint32_t i = 0;
  const Status s = denseIndex(h, &i);  // The handle's status first, then the colour's.
  if (!s.isOk()) return s;
  const Status valid = validateColor(color);
  if (!valid.isOk()) return {valid.code(), "setColor: " + valid.message()};
  colors[i] = (colors[i] & 0xFF000000u) | si::packAppearance(color.r, color.g, color.b, 0);
  changed(i);
  return valid;
}

Status InstanceStore::setCustomLayer(InstanceHandle h, uint8_t custom_layer) {
  return change(h, [&](uint32_t i) {
    colors[i] = (colors[i] & 0x00FFFFFFu) | (uint32_t(custom_layer) << 24);
  });
}

Status InstanceStore::setVariationMask(InstanceHandle h, uint32_t mask) {
  return change(h, [&](uint32_t i) { masks[i] = mask; });
}

Status InstanceStore::play(InstanceHandle h, uint32_t clip, double time_seconds, float speed,
                           double clock) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  if (clip >= palette->clips.size() || !std::isfinite(time_seconds) || !std::isfinite(speed) ||
      speed < 0.0f)
    return {StatusCode::kInvalidArgument,
            "play: clip must be in range, time finite, speed finite and >= 0"};
  if (root_motion[i]) applyRootMotion(*palette, *clip_timings, clock, *this, i);
  endBlend(i, 0.0, clock);
  playback[i] = Playback{clip, palette->clips[clip].loop_mode, speed, clock, time_seconds};
  fade_duration[i] = 0.0;
  events_new[i] = 1;
  changed(i);
  return Status::ok();
}

Status InstanceStore::crossfade(InstanceHandle h, uint32_t clip, double blend_seconds,
                                double time_seconds, double clock) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  if (clip >= palette->clips.size() || !std::isfinite(blend_seconds) || blend_seconds <= 0.0 ||
      !std::isfinite(time_seconds))
    return {StatusCode::kInvalidArgument,
            "crossfade: clip must be in range, blend_seconds finite and > 0, time finite"};
  if (root_motion[i]) applyRootMotion(*palette, *clip_timings, clock, *this, i);
  endBlend(i, blend_seconds, clock);
  fade_from[i] = playback[i];
  fade_start[i] = clock;
  fade_duration[i] = blend_seconds;
  playback[i] = Playback{clip, palette->clips[clip].loop_mode, playback[i].speed, clock,
                         time_seconds};
  events_new[i] = 1;
  changed(i);
  return Status::ok();
}

Status InstanceStore::playOverlay(InstanceHandle h, uint32_t clip, uint32_t mask, float weight,
                                  double blend_seconds, double time_seconds, float speed,
                                  double clock) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  const float from = restartOverlay(i, clock);
  OverlayState& o = overlays[i];
  o.blend = false;  // The new overlay replaces a blend's upper clip; the lower one plays on.
  o.playback = Playback{clip, palette->clips[clip].loop_mode, speed, clock, time_seconds};
  o.mask = mask;
  o.weight_from = blend_seconds > 0.0 ? from : weight;
  o.weight_to = weight;
  for (ExtraLayer& e : o.extra) {  // A 2D blend's other clips fade out with it.
    if (!(blend_seconds > 0.0)) e.weight_from = 0.0f;
    e.weight_to = 0.0f;
  }
  o.fade_start = clock;
  o.fade_duration = blend_seconds;
  changed(i);
  return Status::ok();
}

void InstanceStore::fadeOverlayOut(uint32_t i, double seconds, double clock) {
  OverlayState& o = overlays[i];
  o.blend = false;
  for (uint32_t k = 0; k < kExtraLayers; ++k) {
    o.extra[k].weight_from = seconds > 0.0 ? extraWeight(o, k, clock) : 0.0f;
    o.extra[k].weight_to = 0.0f;
  }
  o.weight_from = seconds > 0.0 ? overlayWeight(o, clock) : 0.0f;
  o.weight_to = 0.0f;
  o.fade_start = clock;
  o.fade_duration = seconds;
}

float InstanceStore::restartOverlay(uint32_t i, double clock) {
  if (root_motion[i]) applyRootMotion(*palette, *clip_timings, clock, *this, i);
  OverlayState& o = overlays[i];
  const float from = o.active ? overlayWeight(o, clock) : 0.0f;
  holdExtraWeights(o, clock);
  if (!o.active) ++overlay_count;
  o.active = true;
  return from;
}

Status InstanceStore::stopOverlay(InstanceHandle h, double blend_seconds, double clock) {
  uint32_t i = 0;
  Status s = denseIndex(h, &i);
  if (!s.isOk()) return s;
  OverlayState& o = overlays[i];
  if (!o.active) return Status::ok();
  if (root_motion[i] && o.blend) applyRootMotion(*palette, *clip_timings, clock, *this, i);
  fadeOverlayOut(i, blend_seconds, clock);
  changed(i);
  return Status::ok();
}

void InstanceStore::markEventsReported(double clock) {
  std::fill(events_clock.begin(), events_clock.end(), clock);
  std::fill(events_new.begin(), events_new.end(), uint8_t(0));
}

}  // namespace si::detail
