// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The per-frame loop, after B. Dudash, "Skinned Instancing" (NVIDIA, 2007): LOD lists per frame
// on the CPU, frustum culling before anything reaches the GPU. Phases as in frame_builder.h.
#include "crowd/frame_builder.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "crowd/cull_lanes.h"
#include "crowd/instance_root_motion.h"
#include "crowd/record_lanes.h"

namespace si::detail {

namespace {

uint32_t floatBits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

uint32_t wornMask(uint32_t mask, uint32_t sub_meshes) {
  return mask & (sub_meshes == 32 ? 0xFFFFFFFFu : ((1u << sub_meshes) - 1u));
}

// The chunk's local group of worn mask `worn` (a new one if unseen; group 0 once the chunk has
// seen kMaxMaskGroups distinct masks: the frame then falls back to one group).
uint32_t localGroup(ChunkWork& w, uint32_t worn) {
  uint32_t h = (worn * 0x9E3779B1u) >> 25;  // 7 bits: 128 slots for at most 64 masks.
  for (;; h = (h + 1) & 127u) {
    const uint8_t slot = w.slot_of[h];
    if (slot == 0xFF) break;
    if (w.masks[slot] == worn) return slot;
  }
  if (w.mask_count == kMaxMaskGroups) {
    w.mask_overflow = true;
    return 0;
  }
  w.masks[w.mask_count] = worn;
  w.slot_of[h] = static_cast<uint8_t>(w.mask_count);
  return w.mask_count++;
}

// The two per-instance loops are compiled twice, for AVX2 and for the baseline, and the loader
// picks one for the CPU it runs on (GCC and Clang on x86-64 ELF). Both round identically: no
// fused multiply-adds (-ffp-contract=off, and "avx2" does not enable FMA).
// Not under the sanitizers: their runtime is not ready when the loader runs the resolver.
#if defined(__has_feature)
#if __has_feature(thread_sanitizer) || __has_feature(address_sanitizer)
#define SI_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SI_SANITIZED 1
#endif
#if defined(__x86_64__) && defined(__ELF__) && !defined(SI_SANITIZED) && \
    (defined(__GNUC__) || defined(__clang__))
#define SI_CPU_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SI_CPU_CLONES
#endif

// Where instance i holds a live pose whose bounds are known (LivePoses::Bounds): its sphere
// into lane k's sphere B, and true.
inline bool setLiveSphere(const InstanceStore& st, uint32_t i, uint32_t k, cull::Lanes& lanes) {
  const uint32_t slot = st.live_slot[i];
  if (slot == kNoLivePose) return false;
  const LivePoses::Bounds& b = st.live.boundsOf(slot);
  if (!b.known) return false;
  lanes.bx[k] = b.sphere.center.x, lanes.by[k] = b.sphere.center.y;
  lanes.bz[k] = b.sphere.center.z, lanes.br[k] = b.sphere.radius;
  return true;
}

// Simulate chunk `chunk`, instances [begin, end): its events and root motion.
void simulateChunk(const FrameInputs& in, InstanceStore& st, uint32_t chunk, uint32_t begin,
                   uint32_t end) {
  const std::vector<ClipTiming>& clips = *in.clips;
  const double clock = in.clock;
  std::vector<AnimationEvent>& events = (*in.chunk_events)[chunk];
  events.clear();
  if (in.markers != nullptr && !in.markers->empty())
    collectEvents(*in.markers, clips, clock, st, begin, end, &events);
  if (in.root_motion)
    applyRootMotion(*in.palette, clips, clock, st, begin, end);  // Before culling.
}

// Calls body(k, i, at, n) for each piece of instances first..first+count that lies in one
// column block: n instances from i (index `at` of its block), into lanes k...
template <typename Body>
__attribute__((always_inline)) inline void forEachColumnPiece(uint32_t first, uint32_t count,
                                                              const Body& body) {
  for (uint32_t k = 0; k < count;) {
    const uint32_t i = first + k, at = i % kColumnBlock;
    const uint32_t n = std::min(count - k, kColumnBlock - at);
    body(k, i, at, n);
    k += n;
  }
}

// A block's camera-relative positions (the float of the double difference) and scales into
// lanes 0..count of `l`, from instances first..first+count (vector loads, a column block at a
// time) or, with `dense`, from instances dense[0..count); lanes count..padded repeat lane 0.
// Inlined: the caller's CPU clone vectorises it.
template <typename Lanes>
__attribute__((always_inline)) inline void loadPositions(const InstanceStore& st,
                                                         const glm::dvec3& camera, uint32_t first,
                                                         const uint32_t* dense, uint32_t count,
                                                         uint32_t padded, Lanes& l) {
  if (dense == nullptr) {
    forEachColumnPiece(first, count, [&](uint32_t k, uint32_t i, uint32_t at, uint32_t n) {
      const DVec3Block& b = st.positions.blockOf(i);
      for (uint32_t j = 0; j < n; ++j) l.rx[k + j] = float(b.x[at + j] - camera.x);
      for (uint32_t j = 0; j < n; ++j) l.ry[k + j] = float(b.y[at + j] - camera.y);
      for (uint32_t j = 0; j < n; ++j) l.rz[k + j] = float(b.z[at + j] - camera.z);
      std::memcpy(l.s + k, st.scales.data() + i, n * sizeof(float));
    });
  } else {
    for (uint32_t k = 0; k < count; ++k) {
      const uint32_t i = dense[k], at = i % kColumnBlock;
      const DVec3Block& b = st.positions.blockOf(i);
      l.rx[k] = float(b.x[at] - camera.x), l.ry[k] = float(b.y[at] - camera.y);
      l.rz[k] = float(b.z[at] - camera.z), l.s[k] = st.scales[i];
    }
  }
  for (uint32_t k = count; k < padded; ++k)
    l.rx[k] = l.rx[0], l.ry[k] = l.ry[0], l.rz[k] = l.rz[0], l.s[k] = l.s[0];
}

// The rotations of the same block (as loadPositions).
template <typename Lanes>
__attribute__((always_inline)) inline void loadRotations(const InstanceStore& st, uint32_t first,
                                                         const uint32_t* dense, uint32_t count,
                                                         uint32_t padded, Lanes& l) {
  if (dense == nullptr) {
    forEachColumnPiece(first, count, [&](uint32_t k, uint32_t i, uint32_t at, uint32_t n) {
      const QuatBlock& b = st.rotations.blockOf(i);
      std::memcpy(l.qx + k, b.x + at, n * sizeof(float));
      std::memcpy(l.qy + k, b.y + at, n * sizeof(float));
      std::memcpy(l.qz + k, b.z + at, n * sizeof(float));
      std::memcpy(l.qw + k, b.w + at, n * sizeof(float));
    });
  } else {
    for (uint32_t k = 0; k < count; ++k) {
      const uint32_t i = dense[k], at = i % kColumnBlock;
      const QuatBlock& b = st.rotations.blockOf(i);
      l.qx[k] = b.x[at], l.qy[k] = b.y[at], l.qz[k] = b.z[at], l.qw[k] = b.w[at];
    }
  }
  for (uint32_t k = count; k < padded; ++k)
    l.qx[k] = l.qx[0], l.qy[k] = l.qy[0], l.qz[k] = l.qz[0], l.qw[k] = l.qw[0];
}

// Select: cull, LOD and key of every instance of chunk `chunk`, instances [begin, end).
SI_CPU_CLONES void selectChunk(const FrameInputs& in, InstanceStore& st, uint32_t chunk,
                               uint32_t begin, uint32_t end, ChunkWork& w) {
  const std::vector<ClipTiming>& clips = *in.clips;
  const cull::Params& cull_params = in.params;
  ViewLanes& view = st.views[in.lane];
  const uint32_t coarsest = in.params.lod_count - 1;
  const uint32_t worn_bits = wornMask(~0u, in.sub_mesh_count);
  const bool live_poses = st.live.count() > 0;
  // Sized for a whole chunk once (never shrunk: no fill per frame); visible_count of them used.
  if (w.visible.size() < end - begin) {
    w.visible.resize(kChunkInstances);
    w.keys.resize(kChunkInstances);
  }
  uint32_t visible = 0;
  w.mask_count = 0;
  w.mask_overflow = false;
  std::memset(w.slot_of, 0xFF, sizeof w.slot_of);
  std::memset(w.counts, 0, sizeof w.counts);
  w.stats = CrowdFrameStats();
  if (in.simulate) simulateChunk(in, st, chunk, begin, end);
  if (in.previous_records) {  // Last selection's slots become the previous ones; none yet now.
    std::copy(view.record_slot.begin() + begin, view.record_slot.begin() + end,
              view.previous_slot.begin() + begin);
    std::fill(view.record_slot.begin() + begin, view.record_slot.begin() + end, kNoPreviousRecord);
  }
  // The selection uses only +, -, * and comparisons in a fixed order (cull_math.h, and
  // cull_lanes.h lane by lane), so the GPU-driven culling pass, which does the same arithmetic,
  // selects exactly the same instances and LODs. Blocks of 64 instances: gathered, selected 8
  // at a time in vector registers, then counted.
  const cull::LodLines lines = cull::lodLines(cull_params);
  cull::Lanes lanes = {};
  for (uint32_t i0 = begin; i0 < end; i0 += cull::kBlock) {
    const uint32_t count = std::min(cull::kBlock, end - i0);
    const uint32_t padded = (count + cull::kLanes - 1) / cull::kLanes * cull::kLanes;
    // Positions and scales first: most of a large crowd may lie beyond the far line, and a
    // block wholly beyond it reads nothing more (selectLanes repeats the same test per lane).
    loadPositions(st, in.camera_position, i0, nullptr, count, padded, lanes);
    bool any_near = false;
    for (uint32_t base = 0; base < padded; base += cull::kLanes)
      any_near |= cull::anyNearLane(cull_params, lanes, base);
    uint32_t fading_groups = 0;  // Bit g: a lane of group g (8 lanes) crossfades.
    if (any_near) {
      loadRotations(st, i0, nullptr, count, padded, lanes);
      for (uint32_t k = 0; k < padded; ++k) {
        const uint32_t i = i0 + (k < count ? k : 0);  // Past the end: lane 0's instance again.
        const ClipTiming& ca = clips[st.playback[i].clip];
        const bool fading = st.fading(i, in.clock);
        const ClipTiming& cb = fading ? clips[st.fade_from[i].clip] : ca;
        lanes.ax[k] = ca.sphere_center.x, lanes.ay[k] = ca.sphere_center.y;
        lanes.az[k] = ca.sphere_center.z, lanes.ar[k] = ca.sphere_radius;
        lanes.bx[k] = cb.sphere_center.x, lanes.by[k] = cb.sphere_center.y;
        lanes.bz[k] = cb.sphere_center.z, lanes.br[k] = cb.sphere_radius;
        // A live pose draws over its clip (and with it while they hand over; a crossfade
        // under it shows its target, clip A): its own sphere is B.
        const bool posed = live_poses && setLiveSphere(st, i, k, lanes);
        fading_groups |= uint32_t(fading || posed) << (k / cull::kLanes);
        lanes.lod[k] = view.lods[i];
      }
    }
    if (!any_near) {
      w.stats.culled_distance += count;
      continue;
    }
    for (uint32_t base = 0; base < padded; base += cull::kLanes)
      cull::selectLanes(cull_params, lines, lanes, base,
                        (fading_groups >> (base / cull::kLanes)) & 1u);
    for (uint32_t k = 0; k < count; ++k) {
      const uint32_t i = i0 + k;
      if (lanes.result[k] != cull::kLaneVisible) {
        ++(lanes.result[k] == cull::kLaneCulledByDistance ? w.stats.culled_distance
                                                          : w.stats.culled_frustum);
        continue;
      }
      view.lods[i] = static_cast<uint8_t>(lanes.lod[k]);  // Hysteresis goes on from it.
      uint32_t lod = std::min(uint32_t(lanes.lod[k]) + in.lod_bias, coarsest);
      // An impostor shows its clip's frames: a live pose stays a mesh, at the last mesh level.
      if (live_poses && in.impostor_lod != 0 && lod >= in.impostor_lod &&
          st.live_slot[i] != kNoLivePose)
        lod = in.impostor_lod - 1;
      const uint32_t worn = in.impostor_lod != 0 && lod >= in.impostor_lod
                                ? 1u  // One impostor per instance, in sub-mesh 0's bucket.
                                : st.masks[i] & worn_bits;
      const uint32_t key = lod * kMaxMaskGroups + localGroup(w, worn);
      ++w.counts[key];
      w.visible[visible] = i;
      w.keys[visible++] = static_cast<uint16_t>(key);
    }
  }
  w.visible_count = visible;
  // Per LOD from the keys' counts (not counted per instance: one counter's increments wait on
  // each other).
  for (uint32_t lod = 0; lod <= coarsest; ++lod)
    for (uint32_t g = 0; g < w.mask_count; ++g)
      w.stats.per_lod[lod] += w.counts[lod * kMaxMaskGroups + g];
}

// The frames and blend of a record playing one clip (no crossfade): B repeats A, weight 0.
void setOneClip(uint32_t frame, uint32_t next_frame, float fraction, IntervalMode mode,
                uint32_t color, InstanceRecord* rec) {
  rec->frames[0] = rec->frames[2] = frame;
  rec->frames[1] = rec->frames[3] = next_frame;
  rec->blend[0] = rec->blend[1] = packFraction(fraction, mode);
  rec->blend[2] = floatBits(0.0f);
  rec->blend[3] = color;
}

// Where instance i holds a live pose (CrowdManager::setLivePose): its record names the live
// frame alone, the engine's pose drawn instead of the clip's; while it hands over (to or from
// the clip), the live frame is clip A and the clip's playback (the record's clip B: a clip
// crossfade under the hand-over shows its target) clip B, at the clip's weight.
inline void setLiveFrame(const InstanceStore& st, uint32_t i, double clock, InstanceRecord* rec) {
  const uint32_t slot = st.live_slot[i];
  if (slot == kNoLivePose) return;
  const float clip_weight = st.live.clipWeight(slot, clock);
  if (clip_weight >= 1.0f) return;
  const uint32_t live = st.live.frameTexel(slot);
  if (clip_weight <= 0.0f) {
    setOneClip(live, live, 0.0f, IntervalMode::kLinear, st.colors[i], rec);
    return;
  }
  rec->frames[0] = rec->frames[1] = live;
  rec->blend[0] = packFraction(0.0f, IntervalMode::kLinear);
  rec->blend[2] = floatBits(clip_weight);
}

// The frames and blend of instance i's record while it crossfades at `clock`: the playback it
// fades from (`from` sampled as `fs`) as the record's clip A, the one it fades to (`to`, `ts`)
// as clip B, weighted by how far the fade has gone.
__attribute__((always_inline)) inline void setCrossfade(
    const InstanceStore& st, uint32_t i, double clock, uint32_t stride, const ClipTiming& from,
    const FrameSample& fs, const ClipTiming& to, const FrameSample& ts, InstanceRecord* rec) {
  const float weight_b = std::min(float((clock - st.fade_start[i]) / st.fade_duration[i]), 1.0f);
  rec->frames[0] = from.first_texel + fs.frame * stride;
  rec->frames[1] = from.first_texel + fs.next_frame * stride;
  rec->frames[2] = to.first_texel + ts.frame * stride;
  rec->frames[3] = to.first_texel + ts.next_frame * stride;
  rec->blend[0] = packFraction(fs.fraction, fs.mode);
  rec->blend[1] = packFraction(ts.fraction, ts.mode);
  rec->blend[2] = floatBits(std::max(0.0f, weight_b));
  rec->blend[3] = st.colors[i];
}

// The frame sample of `pb` playing clip timing `c` at clip-local time `t` (localTime), held on
// the animation-LOD grid with `step`: what scalarRecord samples, from a lane's time.
__attribute__((always_inline)) inline FrameSample sampleAt(const FrameInputs& in,
                                                           const Playback& pb, const ClipTiming& c,
                                                           double t, bool step) {
  if (step) t = steppedTime(t, in.params.animation_step_seconds);
  return fastSample(c, in.palette->clips[pb.clip], t);
}

// Write: every visible instance of the chunk, its record at its place. Blocks of 64: gathered,
// their rows, times and uniform-grid frames computed 8 lanes at a time (record_lanes.h), then
// each record written at its place; a crossfade's second clip, animation-LOD steps, frames
// with frame times and times the lanes could not compute are finished per lane. Each record is
// exactly what scalarRecord writes.
SI_CPU_CLONES void writeChunk(const FrameInputs& in, InstanceStore& st, bool fallback,
                              ChunkWork& w, CrowdFrame& f) {
  ViewLanes& view = st.views[in.lane];
  const uint16_t key_mask = fallback ? uint16_t(~(kMaxMaskGroups - 1)) : uint16_t(0xFFFF);
  const std::vector<ClipTiming>& clips = *in.clips;
  const uint32_t stride = in.palette->layout.frame_stride_texels;
  const uint32_t anim_lod = in.params.animation_lod_start;
  const bool live_poses = st.live.count() > 0;
  RecordLanes lanes = {};
  const size_t n = w.visible_count;
  for (size_t j0 = 0; j0 < n; j0 += kRecordBlock) {
    const uint32_t count = uint32_t(std::min<size_t>(kRecordBlock, n - j0));
    const uint32_t padded = (count + kRecordLanes - 1) / kRecordLanes * kRecordLanes;
    // Transforms by vector loads where the block's instances are consecutive (all in view).
    const uint32_t* dense = w.visible.data() + j0;
    const bool consecutive = dense[count - 1] - dense[0] == count - 1;
    loadPositions(st, in.camera_position, dense[0], consecutive ? nullptr : dense, count, padded,
                  lanes);
    loadRotations(st, dense[0], consecutive ? nullptr : dense, count, padded, lanes);
    for (uint32_t k = 0; k < padded; ++k) {  // Padded with the block's first instance.
      const Playback& pb = st.playback[dense[k < count ? k : 0]];
      const ClipTiming& c = clips[pb.clip];
      lanes.start_time[k] = pb.start_time, lanes.start_clock[k] = pb.start_clock;
      lanes.speed[k] = double(pb.speed);
      lanes.duration[k] = c.duration, lanes.inv_duration[k] = c.inv_duration;
      lanes.inv_interval[k] = c.inv_interval, lanes.last_interval[k] = double(c.last_interval);
      lanes.loop[k] = pb.loop == LoopMode::kLoop ? -1 : 0;
      lanes.scalar[k] = 0;
    }
    for (uint32_t base = 0; base < padded; base += kRecordLanes)
      computeRecordLanes(in.clock, lanes, base);
    for (uint32_t k = 0; k < count; ++k) {
      const uint32_t i = dense[k];
      const uint32_t lod = w.keys[j0 + k] / kMaxMaskGroups;
      const uint32_t slot = w.cursor[w.keys[j0 + k] & key_mask]++;
      InstanceRecord& rec = f.records[slot];
      const float rel[3] = {lanes.rx[k], lanes.ry[k], lanes.rz[k]};
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) rec.world_rows[row][col] = lanes.rows[row][col][k];
        rec.world_rows[row][3] = rel[row];
      }
      const Playback& pb = st.playback[i];
      const ClipTiming& c = clips[pb.clip];
      const bool step = lod >= anim_lod;
      const bool fading = st.fading(i, in.clock);
      if (c.plain && !step && !fading && lanes.scalar[k] == 0) {  // The lanes' frame.
        const uint32_t a0 = c.first_texel + uint32_t(lanes.frame[k]) * stride;
        setOneClip(a0, a0 + stride, lanes.fraction[k], IntervalMode::kLinear, st.colors[i], &rec);
      } else {  // The lane's time, or the scalar one where the lanes could not compute it.
        const FrameSample a = sampleAt(
            in, pb, c, lanes.scalar[k] == 0 ? lanes.time[k] : localTime(pb, c, in.clock), step);
        if (fading) {  // From the old playback to this one.
          const Playback& old = st.fade_from[i];
          const ClipTiming& cb = clips[old.clip];
          const FrameSample b = sampleAt(in, old, cb, localTime(old, cb, in.clock), step);
          setCrossfade(st, i, in.clock, stride, cb, b, c, a, &rec);
        } else {
          setOneClip(c.first_texel + a.frame * stride, c.first_texel + a.next_frame * stride,
                     a.fraction, a.mode, st.colors[i], &rec);
        }
      }
      if (live_poses) setLiveFrame(st, i, in.clock, &rec);
      f.visible_handles[slot] = st.dense_handles[i];
      if (fallback) f.record_masks[slot] = wornMask(st.masks[i], in.sub_mesh_count);
      if (in.layers)
        f.layer_records[slot] = layerRecordsOf(
            st.overlays[i], clips, *in.palette, in.clock,
            in.extra_layers ? &f.extra_layer_records[size_t(slot) * kExtraLayerRecords] : nullptr);
      if (in.previous_records) {
        f.previous_index[slot] = view.previous_slot[i];
        view.record_slot[i] = slot;
      }
    }
  }
}

// Runs `body(c)` for every chunk, on the caller's ParallelFor when there is more than one.
template <typename Body>
void forEachChunk(const FrameInputs& in, uint32_t chunk_count, const Body& body) {
  if (in.parallel_for == nullptr || !*in.parallel_for || chunk_count < 2) {
    for (uint32_t c = 0; c < chunk_count; ++c) body(c);
    return;
  }
  const Body* b = &body;  // One pointer: the std::function stores it without allocating.
  (*in.parallel_for)(chunk_count, ParallelTask([b](uint32_t c) { (*b)(c); }));
}

}  // namespace

void scalarRecord(const FrameInputs& in, const InstanceStore& st, uint32_t i, uint32_t lod,
                  InstanceRecord* out) {
  const BakedPalette& palette = *in.palette;
  const std::vector<ClipTiming>& clips = *in.clips;
  const double clock = in.clock;
  const uint32_t stride = palette.layout.frame_stride_texels;
  const bool step_anim = lod >= in.params.animation_lod_start;
  const double anim_step = in.params.animation_step_seconds;
  const glm::vec3 rel(st.positions.get(i) - in.camera_position);
  const Playback& pb = st.playback[i];
  const ClipTiming& ca = clips[pb.clip];
  InstanceRecord rec;
  const glm::mat3 r = glm::mat3_cast(st.rotations.get(i)) * st.scales[i];
  for (int row = 0; row < 3; ++row) {
    rec.world_rows[row][0] = r[0][row];
    rec.world_rows[row][1] = r[1][row];
    rec.world_rows[row][2] = r[2][row];
    rec.world_rows[row][3] = rel[row];
  }
  double ta = localTime(pb, ca, clock);
  if (step_anim) ta = steppedTime(ta, anim_step);
  const FrameSample fa = fastSample(ca, palette.clips[pb.clip], ta);
  if (st.fading(i, clock)) {  // From the old playback to this one.
    const Playback& old = st.fade_from[i];
    const ClipTiming& cb = clips[old.clip];
    double tb = localTime(old, cb, clock);
    if (step_anim) tb = steppedTime(tb, anim_step);
    const FrameSample fo = fastSample(cb, palette.clips[old.clip], tb);
    setCrossfade(st, i, clock, stride, cb, fo, ca, fa, &rec);
  } else {
    setOneClip(ca.first_texel + fa.frame * stride, ca.first_texel + fa.next_frame * stride,
               fa.fraction, fa.mode, st.colors[i], &rec);
  }
  setLiveFrame(st, i, clock, &rec);
  *out = rec;
}

void buildFrame(const FrameInputs& in, InstanceStore& st, CrowdFrame* frame) {
  CrowdFrame& f = *frame;
  const uint32_t last_visible = f.stats.visible;  // The records the last update wrote.
  const uint32_t n = st.size();
  const uint32_t chunk_count = chunkCount(n);
  f.stats = CrowdFrameStats();
  f.stats.instances = n;
  f.entries_valid = false;
  while (f.chunks.size() < chunk_count) f.chunks.emplace_back();
  forEachChunk(in, chunk_count, [&](uint32_t c) {
    selectChunk(in, st, c, c * kChunkInstances, std::min(n, (c + 1) * kChunkInstances), f.chunks[c]);
  });
  bool fallback = false;
  placeChunks(in, chunk_count, f, &fallback);
  // Motion vectors: the last update's records become the previous ones (a swap, no copy).
  if (in.previous_records) {
    std::swap(f.records, f.previous_records);
    std::swap(f.layer_records, f.previous_layer_records);
    f.previous_layers = f.layers;
    std::swap(f.extra_layer_records, f.previous_extra_layer_records);
    f.previous_extras = f.extras;
    f.previous_visible = last_visible;
  }
  // Grown, never shrunk: records() views the first stats.visible (no zeroing per frame).
  const uint32_t visible = f.stats.visible;
  if (f.records.size() < visible) f.records.resize(visible);
  if (f.visible_handles.size() < visible) f.visible_handles.resize(visible);
  if (in.previous_records && f.previous_index.size() < visible) f.previous_index.resize(visible);
  f.layers = in.layers;
  if (in.layers && f.layer_records.size() < visible) f.layer_records.resize(visible);
  f.extras = in.extra_layers;
  if (f.extras && f.extra_layer_records.size() < size_t(visible) * kExtraLayerRecords)
    f.extra_layer_records.resize(size_t(visible) * kExtraLayerRecords);
  if (fallback && f.record_masks.size() < visible) f.record_masks.resize(visible);
  forEachChunk(in, chunk_count, [&](uint32_t c) { writeChunk(in, st, fallback, f.chunks[c], f); });
  buildBucketRuns(in.params.lod_count, in.sub_mesh_count, fallback, &f);
}

void simulateFrame(const FrameInputs& in, InstanceStore& st) {
  const uint32_t n = st.size();
  forEachChunk(in, chunkCount(n), [&](uint32_t c) {
    simulateChunk(in, st, c, c * kChunkInstances, std::min(n, (c + 1) * kChunkInstances));
  });
}

}  // namespace si::detail
