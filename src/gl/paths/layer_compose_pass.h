// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Composed layers: before a layered crowd is skinned (drawCrowd's vertex shaders or compute
// pre-skinning, both GPU-driven draws), a compute pass composes each overlaid record's
// masked palette slots once per frame (layer_compose.comp.glsl: siLayeredJointRows, the
// overlay's frames and the anchor's, and between weights each masked ancestor's link blended
// in local space), and the skinning reads those rows (siSkinComposed) instead of repeating the
// chain per vertex and influence. RendererDesc::compose_layers turns it off.

#include "gl/paths/draw_path.h"
#include "si/crowd/instance_batcher.h"

namespace si::detail {

/// When RendererDesc::compose_layers is on, the rows (and composed morph weights) of `records`
/// composed records of `masks`' shape (ComposeShape) fit GL_MAX_SHADER_STORAGE_BLOCK_SIZE
/// (layer_compose_table.h) and the pass, flat over them all, fits
/// GL_MAX_COMPUTE_WORK_GROUP_COUNT (dispatch_grid.h): uploads the compose table (storage
/// binding 23), makes the rows buffers hold them (storage bindings 26, and 27 with `previous`:
/// motion vectors) and sets `*lanes` to the pass's invocations per record
/// (ComposeShape::lanes). Otherwise `*lanes` is 0: the draws walk the chain per vertex (the
/// layered programs).
Status prepareComposedRows(const DrawResources& r, Span<const LayerMask> masks, uint64_t records,
                           bool previous, uint32_t* lanes);

/// drawCrowd's compose places (crowd/composed_places.h), for the batches the skinning paths
/// draw, written into `region` (the ring region mapped at frame->ring_base) at the frame's
/// compose blocks; sets frame->compose_records and frame->composed_records.
void writeComposePlaces(const DrawResources& r, const InstanceBatcher& batcher,
                        const CrowdView& view, uint8_t* region, PathFrame* frame);

/// drawCrowd's compose pass: one flat dispatch over the view's records (composed record = the
/// view's record: an instance once, whatever it wears), each read at its first drawn slot (the
/// previous record and layer records too with frame.motion) from the ring bound whole as a
/// storage buffer (binding 24), between two storage barriers: the last draws' reads before,
/// the rows after. Binds each slot's composed record at storage binding 30 for the draws. The
/// mask table (binding 8) is bound; prepareComposedRows' buffers are bound again (it checked
/// that the grid fits). Counts the dispatch and the composed records in `stats`.
void composeLayers(const DrawResources& r, const PathFrame& frame, DrawStats* stats);

/// kUnsupported, naming `who`, when a frame draws a 2D blend's extra layer records (`extras`)
/// without composed rows (`lanes` 0): the per-vertex chain walk composes one overlay only.
Status extrasNeedComposing(const char* who, bool extras, uint32_t lanes);

/// The GPU-driven path's compose pass, after its cull pass: the records and layer records by
/// visible index at storage bindings 4 and 18 (previous ones at 20 and 21 with `motion`), the
/// visible count at 3 (at most `instances`, for which prepareComposedRows checked the dispatch
/// grid), composed record = visible index; the same barriers. 2D blends: the extra layer
/// records from index `extras` of the layer records (`previous_extras` of the previous ones),
/// 2 per visible index; 0: none.
void composeGpuLayers(const DrawResources& r, bool motion, uint32_t lanes, uint32_t instances,
                      uint32_t extras, uint32_t previous_extras, DrawStats* stats);

}  // namespace si::detail
