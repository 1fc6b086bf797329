// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// InstanceBatcher: splits each (LOD, sub-mesh) bucket of a view's selection (si::CrowdView: a
/// CrowdManager's own view(), or a camera of its own) into batches that
/// fit the GPU's uniform block, and writes their std140 records into a caller-provided buffer.
/// The GPU limits arrive as plain numbers (queried once by si::gl), so batching is tested
/// without a GPU.
///
/// Usage:
/// \code
///   si::BatchLimits limits;
///   limits.max_uniform_block_size_bytes = info.max_uniform_block_size_bytes;   // from si::gl
///   limits.uniform_buffer_offset_alignment = info.uniform_buffer_offset_alignment;
///   si::InstanceBatcher batcher;
///   si::Status s = batcher.init(limits);
///   const si::CrowdView& view = crowd.view();     // after crowd.update(dt, camera)
///   std::vector<uint8_t> records(batcher.recordBufferBound(view));
///   std::vector<si::DrawBatch> draws;
///   s = batcher.build(view, records, &draws);
///   // One glBindBufferRange + glDrawElementsInstanced per draw.
/// \endcode

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/span.h"
#include "si/core/status.h"
#include "si/crowd/crowd_view.h"

namespace si {

/// The GPU limits batching depends on.
struct BatchLimits {
  /// GL_MAX_UNIFORM_BLOCK_SIZE; at least 16384 (GL's minimum). Required.
  uint32_t max_uniform_block_size_bytes = 0;
  /// GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT; a power of two, 0 means 256.
  uint32_t uniform_buffer_offset_alignment = 0;
  /// Instances per draw the shader's block array holds; 0 means as many as fit in the block.
  uint32_t max_instances_per_draw = 0;
};

/// One instanced draw: `instance_count` records of kInstanceRecordSize bytes starting at
/// `byte_offset` (a multiple of the offset alignment) in the record buffer.
struct DrawBatch {
  uint16_t lod = 0;
  uint16_t sub_mesh = 0;
  uint32_t byte_offset = 0;
  uint32_t instance_count = 0;
  /// Layered animation: where buildLayers() puts the batch's layer records (kLayerRecordSize
  /// bytes each, a multiple of the offset alignment) in the layer buffer.
  uint32_t layer_byte_offset = 0;
};

/// One draw straight from the crowd's records (InstanceBatcher::buildSpans, no copy): its
/// instance k is records()[first_record + k]. To read it from a uniform block, bind the records
/// from `block_first_record` on (block_first_record * 80 bytes is a multiple of the batcher's
/// alignment, so if the buffer holding records() starts aligned, so does the binding) and read
/// element (first_record - block_first_record) + gl_InstanceID, which stays below
/// capacityPerDraw(). A shader that reads the records from a storage buffer ignores the block.
struct RecordSpanDraw {
  uint16_t lod = 0;
  uint16_t sub_mesh = 0;
  uint32_t first_record = 0;
  uint32_t instance_count = 0;
  uint32_t block_first_record = 0;
};

/// The shift buildPrevious() adds to the translation of a record without a previous one: the
/// view's last camera position minus the previous one's, as floats (the record moves from the
/// last camera's origin to the previous one's); 0 where they are 1e30 or more apart, past a
/// float. A shader reading previous records through buildPreviousIndices() adds it the same way.
glm::vec3 previousRecordShift(const CrowdView& view);
/// The same from a camera's position now and its previous one (the GPU-driven paths' views,
/// whose cameras the renderer keeps).
glm::vec3 previousRecordShift(const glm::dvec3& now, const glm::dvec3& then);

/// Stateless apart from its limits: build() is deterministic for the same selection.
class InstanceBatcher {
 public:
  /// Adopts the limits. kInvalidArgument when the block is smaller than 16384 bytes, the
  /// alignment is not a power of two, or max_instances_per_draw exceeds what the block holds.
  Status init(const BatchLimits& limits);

  /// Records per draw: floor(max block size / 80), or max_instances_per_draw if smaller.
  /// 819 for 64 KiB, 204 for 16 KiB.
  uint32_t capacityPerDraw() const { return capacity_; }
  /// The alignment in use.
  uint32_t alignment() const { return alignment_; }

  /// Bytes build() needs for `view`'s last selection: each batch padded to the alignment.
  size_t recordBufferBound(const CrowdView& view) const;

  /// Splits every bucket of `view`'s last selection into batches of at most capacityPerDraw()
  /// instances (buckets in order: LOD-major, then sub-mesh), copies their records into `out`
  /// and replaces `draws` with the draw list. kInvalidArgument if not initialized or `draws` is
  /// null; kCountMismatch when `out` is smaller than recordBufferBound(view) (nothing written).
  /// Does not allocate once `draws` has reached the needed capacity.
  Status build(const CrowdView& view, Span<uint8_t> out, std::vector<DrawBatch>* draws) const;

  /// Motion vectors: writes, in build()'s layout (the same draws, byte offsets and slots), each
  /// instance's record of the previous update (CrowdView::previousRecords()), relative to
  /// the previous update's camera. Where an instance has none (kNoPreviousRecord: not drawn
  /// then, added or teleported since), its slot holds its current record moved to the previous
  /// camera's origin: it has not moved, only the camera has (kept where the cameras are 1e30
  /// or more apart, past a float). Bind it beside the current block
  /// (si_skinning.glsl's SiPreviousInstances, SI_PREVIOUS_RECORDS) and project with the
  /// previous camera. kInvalidArgument if not initialized or the crowd does not keep previous
  /// records (CrowdDesc::previous_records); kCountMismatch when `out` is smaller than
  /// recordBufferBound(view) (nothing written).
  Status buildPrevious(const CrowdView& view, Span<uint8_t> out) const;

  /// Motion vectors without a copy of each previous record per slot: bytes
  /// buildPreviousIndices() needs (4 per slot, in buildLayers()' slot numbering:
  /// layerBufferBound() / 4).
  size_t previousIndexBufferBound(const CrowdView& view) const;
  /// Writes, for each slot of build()'s draws, the index of its instance's previous record in
  /// previousRecords() (CrowdView::previousRecordIndices(); kNoPreviousRecord
  /// where it has none, for which a shader takes buildPrevious()'s fallback: the current record
  /// moved by the cameras' shift) as a 32-bit word at (layer_byte_offset / 16 + slot) * 4. With
  /// previousRecords() uploaded once beside it, a shader reads each previous record through
  /// its slot's index: 4 bytes a slot instead of buildPrevious()'s 80 (what drawCrowd does).
  /// kInvalidArgument if not initialized or the crowd keeps no previous records; kCountMismatch
  /// when `out` is smaller than previousIndexBufferBound() (nothing written).
  Status buildPreviousIndices(const CrowdView& view, Span<uint8_t> out) const;
  /// The same through a table: writes `previous_places[p]` instead of each index p (what
  /// buildRecordPlaces() gave for the previous selection: the 16-byte word of each previous
  /// record in the buffer the previous frame's build() wrote), so a shader reads the previous
  /// records where that frame left them, with no copy (what drawCrowd does while that buffer is
  /// intact). kNoPreviousRecord stays where there is no previous record or the table has none
  /// (kNoRecordPlace). kCountMismatch also when `previous_places` holds fewer entries than
  /// previousRecords() (nothing written).
  Status buildPreviousIndices(const CrowdView& view, Span<uint8_t> out,
                              Span<const uint32_t> previous_places) const;

  /// Where build() puts each record: for each of records(), the 16-byte word (byte offset / 16)
  /// in build()'s buffer of one of its copies (the last in build()'s order), or kNoRecordPlace
  /// where no batch holds it. kInvalidArgument if not initialized; kCountMismatch when `out`
  /// holds fewer entries than records() (nothing written).
  Status buildRecordPlaces(const CrowdView& view, Span<uint32_t> out) const;
  static constexpr uint32_t kNoRecordPlace = 0xFFFFFFFFu;

  /// Materials that read the drawn instance's handle (si::MaterialDesc::instance_handle):
  /// bytes buildHandles() needs (4 per slot, in buildLayers()' slot numbering).
  size_t handleBufferBound(const CrowdView& view) const;
  /// Writes, for each slot of build()'s draws, its instance's InstanceHandle::id
  /// (CrowdView::visibleHandles()) as a 32-bit word at (layer_byte_offset / 16 + slot) * 4: a
  /// shader finds its instance's handle at its batch's first slot plus gl_InstanceID (what
  /// drawCrowd does, shaders/instance_handle.glsl). kInvalidArgument if not initialized;
  /// kCountMismatch when `out` is smaller than handleBufferBound() (nothing written).
  Status buildHandles(const CrowdView& view, Span<uint8_t> out) const;

  /// Layered animation: bytes buildLayers() needs (each batch's layer records padded to the
  /// alignment).
  size_t layerBufferBound(const CrowdView& view) const;
  /// Writes each batch's layer records (CrowdView::layerRecords(), 16 bytes a slot) at its
  /// layer_byte_offset, in the slots build() gives its records: bind a batch's at
  /// si_skinning.glsl's SiLayers (SI_LAYERS) beside its records. kInvalidArgument if not
  /// initialized or the crowd's last update wrote no layer records; kCountMismatch when `out`
  /// is smaller than layerBufferBound(view) (nothing written).
  Status buildLayers(const CrowdView& view, Span<uint8_t> out) const;
  /// Motion vectors of overlays: buildLayers()'s layout holding each slot's previous layer
  /// record (CrowdView::previousLayerRecords() through previousRecordIndices()); where the
  /// instance has no previous record, its current layer record (buildPrevious()'s fallback);
  /// where the previous update wrote no layer records, a zero record (no overlay then).
  /// kInvalidArgument as buildLayers(), or when the crowd keeps no previous records;
  /// kCountMismatch when `out` is smaller than layerBufferBound(view).
  Status buildPreviousLayers(const CrowdView& view, Span<uint8_t> out) const;

  /// 2D blends (CrowdView::extraLayerRecords): bytes buildExtraLayers() needs, two records
  /// a slot of buildLayers()' slot numbering (layerBufferBound() * 2).
  size_t extraLayerBufferBound(const CrowdView& view) const;
  /// Writes each slot's kExtraLayerRecords extra layer records at
  /// ((layer_byte_offset / 16 + slot) * 2 + k) * 16, in the slots build() gives its records
  /// (one storage buffer for the frame; drawCrowd's compose pass reads it).
  /// kInvalidArgument if not initialized or the crowd's last update wrote no extra layer
  /// records (no 2D blend space); kCountMismatch when `out` is smaller than
  /// extraLayerBufferBound() (nothing written).
  Status buildExtraLayers(const CrowdView& view, Span<uint8_t> out) const;
  /// Motion vectors of 2D blends: buildExtraLayers()'s layout holding each slot's previous
  /// extra layer records (CrowdView::previousExtraLayerRecords() through
  /// previousRecordIndices()), with buildPreviousLayers()' fallbacks. kInvalidArgument as
  /// buildExtraLayers(), or when the crowd keeps no previous records; kCountMismatch as
  /// buildExtraLayers().
  Status buildPreviousExtraLayers(const CrowdView& view, Span<uint8_t> out) const;

  /// The same draws without copying a record: each bucket's runs (CrowdView::bucketRuns)
  /// cut where a block would exceed capacityPerDraw(). An application uploads records() once
  /// (80 bytes per visible instance, instead of 80 per worn sub-mesh) and binds each draw's
  /// block as RecordSpanDraw says. More draws than build() when instances differ in worn
  /// sub-meshes (one per run). kInvalidArgument if not initialized or `draws` is null;
  /// kUnsupported when the alignment is too coarse for spans (a block start more than
  /// capacityPerDraw() records before a run; not with GL's usual alignments of 256 or less).
  /// Does not allocate once `draws` has reached the needed capacity.
  Status buildSpans(const CrowdView& view, std::vector<RecordSpanDraw>* draws) const;

 private:
  // buildPrevious' and buildPreviousIndices' checks: initialized, previous records kept, `out`
  // (the `buffer` buffer) holding `needed` bytes (named `what`).
  Status checkPreviousBuffer(const char* what, const char* buffer, const CrowdView& view,
                             size_t out_bytes, size_t needed) const;
  // buildLayers' checks (`extra`: buildExtraLayers'; `previous`: the buildPrevious ones'):
  // initialized, previous records kept, those records written, `out` large enough (named
  // `what`).
  Status checkLayerBuffer(const char* what, const CrowdView& view, size_t out_bytes, bool extra,
                          bool previous) const;
  uint32_t capacity_ = 0;
  uint32_t alignment_ = 0;
};

}  // namespace si
