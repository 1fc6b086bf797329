// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd's per-frame work after the clock advanced: the simulation (events, root motion;
// once per frame) and a view's selection (CrowdManager::update does both in one
// pass, CrowdManager::advance the first, CrowdView::select the second), in three phases over
// fixed chunks of instances, the first and last run as parallel tasks:
//   select (per chunk)  [the simulation,] far-line and frustum culling, LOD with hysteresis;
//                       each visible instance gets a key (LOD, worn-mask group);
//   place (serial)      the chunks' distinct worn masks merged and sorted, every key's place in
//                       the records by prefix sums (key-major, then chunk, then dense order);
//   write (per chunk)   each visible instance's record written once, at its place.
// The records thus lie sorted by (LOD, worn mask, dense index), whatever the thread count, so
// each (LOD, sub-mesh) bucket is a few runs of consecutive records (bucket_runs.cpp).

#include <cstdint>
#include <vector>

#include "crowd/animation_events.h"
#include "crowd/instance_store.h"
#include "si/crowd/animation_event.h"
#include "si/crowd/crowd_desc.h"
#include "si/crowd/crowd_view.h"
#include "si/crowd/parallel_for.h"

namespace si::detail {

/// Instances per task. A multiple of 64; small enough to balance 16 threads at 100k.
inline constexpr uint32_t kChunkInstances = 4096;
static_assert(kChunkInstances % kStampChunk == 0, "tasks stamp disjoint chunks (root motion)");
/// Distinct worn masks per frame that get a group of their own; past this the frame falls back
/// to one group per LOD (records in dense order; runs found by scanning).
inline constexpr uint32_t kMaxMaskGroups = 64;

/// One chunk's work between the phases.
struct ChunkWork {
  std::vector<uint32_t> visible;      // Dense indices of its visible instances, in order,
  std::vector<uint16_t> keys;         // and their keys (lod * kMaxMaskGroups + local group):
  uint32_t visible_count = 0;         // the first visible_count of each (sized for a chunk).
  uint32_t masks[kMaxMaskGroups];     // Local group -> worn mask.
  uint32_t to_group[kMaxMaskGroups];  // Local group -> the frame's group (set by place).
  uint32_t mask_count = 0;
  bool mask_overflow = false;
  uint8_t slot_of[128];                 // Open-addressed worn mask -> local group (0xFF: empty).
  uint32_t counts[8 * kMaxMaskGroups];  // Per local key.
  uint32_t cursor[8 * kMaxMaskGroups];  // Per local key: the next record to write.
  CrowdFrameStats stats;
};

/// One frame's output, reused between frames (allocates only while the crowd grows).
struct CrowdFrame {
  CrowdFrameStats stats;
  std::vector<InstanceRecord> records;          // Sorted by (LOD, worn mask, dense index).
  std::vector<InstanceHandle> visible_handles;  // Parallel to records.
  // Motion vectors (FrameInputs::previous_records): the previous update's records (its first
  // previous_visible), and per record the index of the instance's record in them.
  std::vector<InstanceRecord> previous_records;
  uint32_t previous_visible = 0;
  std::vector<uint32_t> previous_index;
  // Layered animation (FrameInputs::layers): parallel to records; with previous records, the
  // previous update's too (parallel to previous_records, when that update wrote them).
  std::vector<LayerRecord> layer_records;
  bool layers = false;  // Whether this frame wrote them.
  std::vector<LayerRecord> previous_layer_records;
  bool previous_layers = false;
  // With FrameInputs::extra_layers, kExtraLayerRecords per record: 2D blends' extra layers.
  std::vector<LayerRecord> extra_layer_records;
  bool extras = false;
  std::vector<LayerRecord> previous_extra_layer_records;
  bool previous_extras = false;
  std::vector<uint32_t> record_masks;           // Parallel: worn masks.
  std::vector<ChunkWork> chunks;
  // Groups of this frame: the distinct worn masks in increasing order, and the record ranges
  // of each (LOD, group), key-major.
  std::vector<uint32_t> group_masks;
  std::vector<uint32_t> key_offsets;  // lod_count * groups + 1 prefix sums.
  std::vector<uint32_t> bucket_cursor_scratch;
  // Buckets: per (LOD, sub-mesh) its runs of consecutive records.
  std::vector<uint32_t> bucket_offsets;  // bucket_count + 1: entries per bucket, summed.
  std::vector<uint32_t> run_offsets;     // bucket_count + 1: runs per bucket, summed.
  std::vector<RecordRun> runs;
  // bucketEntries(), expanded from the runs when first asked for.
  std::vector<uint32_t> bucket_entries;
  bool entries_valid = false;
};

/// What a frame is built from besides the instances.
struct FrameInputs {
  const BakedPalette* palette = nullptr;
  const std::vector<ClipTiming>* clips = nullptr;  // Per palette clip.
  CullParams params;                               // CrowdExport::cullParams(view, camera).
  glm::dvec3 camera_position{0.0};
  double clock = 0.0;  // The crowd clock, already advanced.
  uint32_t sub_mesh_count = 1;
  uint32_t impostor_lod = 0;  // CrowdDesc::impostor_lod: its instances join sub-mesh 0's bucket.
  const ParallelFor* parallel_for = nullptr;  // Null: every task on the calling thread.
  const MarkerTable* markers = nullptr;       // Null or empty: no events.
  bool root_motion = false;                   // Some instance opted in to root motion.
  bool previous_records = false;              // CrowdDesc::previous_records.
  bool layers = false;                        // Some instance played an overlay.
  bool extra_layers = false;  // Implies layers: the crowd holds a 2D blend space too.
  // The view: its lane of the store (InstanceStore::views) and its LOD bias.
  uint32_t lane = 0;
  uint32_t lod_bias = 0;
  // The simulation in the same pass (CrowdManager::update), its events into chunk_events[c]
  // for chunk c (grown to the chunk count).
  bool simulate = false;
  std::vector<std::vector<AnimationEvent>>* chunk_events = nullptr;
};

/// Builds `frame` from `store` for the view of lane in.lane, updating that lane's LODs and,
/// with in.simulate, simulating first (the LODs do not change the state version: the
/// GPU-driven pass does the same). A crossfade runs while InstanceStore::fading says so.
void buildFrame(const FrameInputs& in, InstanceStore& store, CrowdFrame* frame);
/// The simulation alone (CrowdManager::advance): root motion and events into
/// in.chunk_events (in.palette, clips, clock, markers, root_motion and parallel_for are read).
void simulateFrame(const FrameInputs& in, InstanceStore& store);
/// The record of visible instance `i` (dense index) at LOD `lod`, one instance at a time in
/// scalar code: what buildFrame writes for it, block by block (the reference its tests hold the
/// block path to).
void scalarRecord(const FrameInputs& in, const InstanceStore& st, uint32_t i, uint32_t lod,
                  InstanceRecord* out);
/// Chunks of a store of `n` instances.
inline uint32_t chunkCount(uint32_t n) { return (n + kChunkInstances - 1) / kChunkInstances; }

/// Place: the frame's groups (f.group_masks; *fallback when past kMaxMaskGroups), the record
/// range of every key (f.key_offsets), each chunk's cursors, and f.stats summed from the chunks'.
void placeChunks(const FrameInputs& in, uint32_t chunk_count, CrowdFrame& f, bool* fallback);
/// The bucket runs of a placed frame (frame.key_offsets and group_masks set, records written;
/// in the fallback, record_masks too).
void buildBucketRuns(uint32_t lod_count, uint32_t sub_mesh_count, bool fallback, CrowdFrame* frame);
/// Fills frame.bucket_entries from the runs.
void expandBucketEntries(CrowdFrame* frame);

}  // namespace si::detail
