// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The compose pass of layered animation: each overlaid record's masked joints, once a frame.
#include "gl/paths/layer_compose_pass.h"

#include <algorithm>
#include <string>

#include "crowd/composed_places.h"
#include "crowd/layer_compose_table.h"
#include "gl/paths/dispatch_grid.h"

namespace si::detail {

Status prepareComposedRows(const DrawResources& r, Span<const LayerMask> masks, uint64_t records,
                           bool previous, uint32_t* lanes) {
  *lanes = 0;
  if (!r.desc->compose_layers) return Status::ok();
  const std::vector<int32_t> table = layerComposeTable(masks);
  const ComposeShape shape = composeShape(table);
  const uint64_t limit = r.info->max_shader_storage_block_size_bytes;
  DispatchGrid grid;
  const bool dispatch_fits =
      dispatchGrid((records * shape.lanes() + 63) / 64, r.info->max_compute_groups_x,
                   r.info->max_compute_groups_y, &grid);
  if (!composedRowsFit(limit, records, shape) || !dispatch_fits) return Status::ok();
  LayerComposeBuffers& buffers = r.scratch->layer_compose;
  Status s = buffers.uploadTable(table);
  if (s.isOk()) s = buffers.ensureRows(composedRowBytes(records, shape), limit, previous);
  if (s.isOk()) *lanes = shape.lanes();
  return s;
}

void writeComposePlaces(const DrawResources& r, const InstanceBatcher& batcher,
                        const CrowdView& view, uint8_t* region, PathFrame* f) {
  // The batches the skinning paths draw (CharacterBuffers::drawnRange): the others need no
  // rows.
  const uint32_t sub_meshes = view.subMeshCount();
  const uint32_t buckets = uint32_t(view.bucketOffsets().size()) - 1;
  std::vector<uint8_t> drawn(buckets, 0);
  for (uint32_t b = 0; b < buckets; ++b)
    drawn[b] = r.character->drawnRange(b % sub_meshes, b / sub_meshes).index_count > 0;
  f->compose_records = uint32_t(view.records().size());
  const size_t entries = f->compose_entries_base - f->ring_base;
  const size_t slots = f->compose_slots_base - f->ring_base;
  f->composed_records = writeComposedPlaces(
      batcher, view, drawn,
      Span<uint32_t>(reinterpret_cast<uint32_t*>(region + entries), size_t(f->compose_records) * 2),
      Span<uint32_t>(reinterpret_cast<uint32_t*>(region + slots), f->compose_slot_bytes / 4));
}

void composeLayers(const DrawResources& r, const PathFrame& f, DrawStats* st) {
  const Program& compose =
      r.programs[f.motion ? ProgramId::kLayerComposeMotion : ProgramId::kLayerCompose];
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // Earlier draws are done reading the rows.
  glUseProgram(compose.id);
  r.palette->bind();
  r.scratch->layer_compose.bind(f.motion);
  r.ring->bindRegion(f.ring_base, f.ring_bytes, 24);
  if (f.compose_slot_bytes > 0) r.ring->bindRegion(f.compose_slots_base, f.compose_slot_bytes, 30);
  // The previous records through their indices; the previous layer records in the same slots
  // at their block's offset.
  if (f.motion) bindPreviousRecords(r, compose, f);
  const auto word = [&](uint64_t base) { return uint32_t((base - f.ring_base) / 16); };
  glProgramUniform4ui(compose.id, 5, word(f.compose_entries_base), f.compose_records,
                      word(f.layer_base),
                      f.motion ? uint32_t((f.previous_layer_base - f.layer_base) / 16) : 0u);
  // 2D blends' extra layer records, by word from the region's start (0: none).
  glProgramUniform2ui(compose.id, 6, f.extras ? word(f.extra_layer_base) : 0u,
                      f.extras && f.motion ? word(f.previous_extra_base) : 0u);
  const uint64_t invocations = uint64_t(f.compose_records) * f.compose_lanes;
  // prepareComposedRows checked that the grid holds them: dispatchGroups cannot refuse.
  (void)dispatchGroups(*r.info, (invocations + 63) / 64, "composed layers");
  ++st->compose_dispatches;
  st->composed_records += f.composed_records;
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // The rows before the draws read them.
}

Status extrasNeedComposing(const char* who, bool extras, uint32_t lanes) {
  if (!extras || lanes > 0) return Status::ok();
  return {StatusCode::kUnsupported,
          std::string(who) +
              ": 2D blends are drawn through composed layers, and these do not fit "
              "(RendererDesc::compose_layers off, or the rows past "
              "GL_MAX_SHADER_STORAGE_BLOCK_SIZE or the compute grid): draw fewer instances"};
}

void composeGpuLayers(const DrawResources& r, bool motion, uint32_t lanes, uint32_t instances,
                      uint32_t extras, uint32_t previous_extras, DrawStats* st) {
  const Program& compose =
      r.programs[motion ? ProgramId::kGpuLayerComposeMotion : ProgramId::kGpuLayerCompose];
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // The cull pass's records; earlier reads.
  glUseProgram(compose.id);
  r.palette->bind();
  r.scratch->layer_compose.bind(motion);
  glProgramUniform3ui(compose.id, 5, instances, extras, motion ? previous_extras : 0u);
  const uint64_t invocations = uint64_t(instances) * lanes;
  // prepareComposedRows checked that the grid holds them: dispatchGroups cannot refuse.
  (void)dispatchGroups(*r.info, (invocations + 63) / 64, "composed layers");
  ++st->compose_dispatches;
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

}  // namespace si::detail
