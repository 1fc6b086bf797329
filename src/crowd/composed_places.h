// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Where drawCrowd's layer compose pass finds each instance, so that it composes an overlaid
// instance once however many sub-meshes it wears: the composed rows are keyed by the view's
// record (one per visible instance), and each drawn slot of InstanceBatcher's numbering names
// its record. No GL.

#include <cstdint>

#include "si/core/span.h"
#include "si/crowd/crowd_view.h"
#include "si/crowd/instance_batcher.h"

namespace si::detail {

/// An entry of a record drawn in no batch.
inline constexpr uint32_t kNotComposed = 0xFFFFFFFFu;

/// For `view`'s last selection batched by `batcher`, in the batches of the buckets that
/// `drawn_buckets` marks non-zero (bucket lod * sub-meshes + sub-mesh; the batches the
/// skinning paths draw): `entries` (2 words per record of view.records()) gets each drawn
/// record's first slot, as its record's 16-byte word in build()'s buffer and its slot in
/// buildLayers()' numbering (DrawBatch::layer_byte_offset / 16 + place), kNotComposed in both
/// for a record drawn nowhere; `slot_records` (layerBufferBound() / 16 words) gets each drawn
/// slot's record index. Returns the records drawn. `batcher` is initialized; the spans hold
/// what they must (checked by the caller, whose ring block sizes them).
uint32_t writeComposedPlaces(const InstanceBatcher& batcher, const CrowdView& view,
                             Span<const uint8_t> drawn_buckets, Span<uint32_t> entries,
                             Span<uint32_t> slot_records);

}  // namespace si::detail
