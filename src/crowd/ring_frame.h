// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What a draw of the batched paths (si::gl's drawCrowd, si::vk's recordDraw) writes into its
// region of the record ring, and where: the batches' records;
// with motion vectors each slot's previous-record index and, unless the previous frame's region
// still holds them (si::gl's resources/drawn_regions.h; si::vk always copies them), the
// previous records once each;
// with overlays the layer records (and previous layer records), a 2D blend's extra layer
// records (and previous ones) and the compose pass's places (crowd/composed_places.h: per
// record its first drawn slot, per slot its record); for a material that reads the instance
// handle, each slot's handle. Offsets are from the region's start, each block at the
// next multiple of the alignment.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "si/core/status.h"
#include "si/crowd/instance_batcher.h"

namespace si::detail {

/// What a frame writes beside the batches' records.
struct RingContents {
  bool motion = false;   ///< Previous-record indices (and the previous records when copied).
  bool layers = false;   ///< Layer records (overlays), extra ones for 2D blends.
  bool handles = false;  ///< Each slot's instance handle (MaterialDesc::instance_handle).
};

struct RingFrame {
  bool motion = false, layers = false;
  bool previous_copied = false;  ///< Motion: the previous records are written here.
  size_t records_end = 0;        ///< InstanceBatcher::build's records, from 0.
  size_t previous_indices = 0;   ///< buildPreviousIndices (4 bytes a slot).
  size_t previous_records = 0;   ///< When copied: CrowdView::previousRecords(), 80 bytes each.
  size_t previous_end = 0;       ///< The end of the indices, or of the copied records.
  size_t layer_records = 0;      ///< buildLayers.
  size_t previous_layers = 0;    ///< buildPreviousLayers.
  bool extras = false;           ///< 2D blends: the extra layer records too.
  size_t extra_layers = 0;       ///< buildExtraLayers.
  size_t previous_extras = 0;    ///< buildPreviousExtraLayers.
  size_t compose_entries = 0;    ///< writeComposedPlaces' entries (8 bytes a record),
  size_t compose_slots = 0;      ///< and its slots' records (4 bytes a slot).
  bool handles = false;
  size_t handle_words = 0;  ///< buildHandles (4 bytes a slot).
  size_t handles_end = 0;
  uint64_t layer_slots = 0;  ///< Layer records the layer block holds (padding included).
  size_t end = 0;            ///< Bytes of the region the frame may use.
};

/// Where each block of `view`'s frame goes for `batcher` (`alignment`: a power of two, the
/// uniform and storage buffer offset alignments' larger) holding `contents`; with motion,
/// whether the previous records are copied into the region (`copy_previous`).
RingFrame planRingFrame(const InstanceBatcher& batcher, const CrowdView& view, uint32_t alignment,
                        const RingContents& contents, bool copy_previous);

/// Writes the planned blocks (all but the compose pass's places) at `region` (`bytes` writable) and
/// replaces `batches` with the draws. With motion and records not copied, each slot's index is
/// its previous record's word in `previous_places` (InstanceBatcher::buildRecordPlaces of the
/// previous selection's draw). The batcher's status on failure.
Status writeRingFrame(const InstanceBatcher& batcher, const CrowdView& view, const RingFrame& plan,
                      uint8_t* region, size_t bytes, Span<const uint32_t> previous_places,
                      std::vector<DrawBatch>* batches);

}  // namespace si::detail
