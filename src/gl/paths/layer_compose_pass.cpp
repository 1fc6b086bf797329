// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The compose pass of layered animation: each overlaid record's masked joints, once a frame.
#include "gl/paths/layer_compose_pass.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "gl/paths/dispatch_grid.h"
#include "gl/resources/layer_compose_table.h"

namespace si::detail {

Status prepareComposedRows(const DrawResources& r, Span<const LayerMask> masks, uint64_t records,
                           uint32_t batch_records, bool previous, uint32_t* stride) {
  *stride = 0;
  if (!r.desc->compose_layers) return Status::ok();
  const std::vector<int32_t> table = layerComposeTable(masks);
  const uint64_t limit = r.info->max_shader_storage_block_size_bytes;
  const uint32_t masked = uint32_t(table[1]);
  DispatchGrid grid;
  const bool dispatch_fits =
      batch_records > 0
          ? (uint64_t(batch_records) * masked + 63) / 64 <= groupLimit(r.info->max_compute_groups_x)
          : dispatchGrid((records * masked + 63) / 64, r.info->max_compute_groups_x,
                         r.info->max_compute_groups_y, &grid);
  if (!composedRowsFit(limit, records, masked) || !dispatch_fits) return Status::ok();
  LayerComposeBuffers& buffers = r.scratch->layer_compose;
  Status s = buffers.uploadTable(table);
  if (s.isOk())
    s = buffers.ensureRows(composedRowBytes(records, uint32_t(table[1])), limit, previous);
  if (s.isOk()) *stride = uint32_t(table[1]);
  return s;
}

namespace {

// Whether the skinning paths draw batch `d` (vertex_shader_path.cpp, compute_path.cpp): the
// others need no rows.
bool drawn(const DrawResources& r, const DrawBatch& d) {
  return d.sub_mesh < r.character->sub_meshes.size() &&
         r.character->lodRange(d.sub_mesh, d.lod).index_count > 0;
}

}  // namespace

uint32_t writeComposeBatches(const DrawResources& r, const PathFrame& f, uint8_t* out) {
  uint32_t n = 0;
  for (const DrawBatch& d : *f.batches) {
    if (!drawn(r, d)) continue;
    // Words from the region's start.
    const uint32_t entry[4] = {uint32_t(d.byte_offset / 16),
                               uint32_t((f.layer_base - f.ring_base + d.layer_byte_offset) / 16),
                               d.instance_count, d.layer_byte_offset / kLayerRecordSize};
    std::memcpy(out + size_t(n++) * sizeof entry, entry, sizeof entry);
  }
  return n;
}

void composeLayers(const DrawResources& r, const PathFrame& f, DrawStats* st) {
  const uint32_t stride = f.compose_stride;
  uint32_t most = 0;  // The largest batch: the groups of every row.
  uint64_t records = 0;
  for (const DrawBatch& d : *f.batches)
    if (drawn(r, d)) {
      most = std::max(most, d.instance_count);
      records += d.instance_count;
    }
  const uint64_t groups_x = (uint64_t(most) * stride + 63) / 64;  // Fits: prepareComposedRows.
  const uint32_t max_y = groupLimit(r.info->max_compute_groups_y);
  const Program& compose =
      r.programs[f.motion ? ProgramId::kLayerComposeMotion : ProgramId::kLayerCompose];
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // Earlier draws are done reading the rows.
  glUseProgram(compose.id);
  r.palette->bind();
  r.scratch->layer_compose.bind(f.motion);
  r.ring->bindRegion(f.ring_base, f.ring_bytes, 24);
  if (f.motion) {  // The previous records through their indices; the previous layer records
                   // in the same slots at their block's offset.
    bindPreviousRecords(r, compose, f);
    glProgramUniform1ui(compose.id, 6, uint32_t((f.previous_layer_base - f.layer_base) / 16));
  }
  // 2D blends' extra layer records, by word from the region's start (0: none).
  glProgramUniform1ui(compose.id, 7,
                      f.extras ? uint32_t((f.extra_layer_base - f.ring_base) / 16) : 0u);
  if (f.motion)
    glProgramUniform1ui(compose.id, 10,
                        f.extras ? uint32_t((f.previous_extra_base - f.ring_base) / 16) : 0u);
  const uint32_t table = uint32_t((f.compose_table_base - f.ring_base) / 16);
  for (uint32_t first = 0; first < f.compose_batches; first += max_y) {
    const uint32_t rows = std::min(f.compose_batches - first, max_y);
    glProgramUniform1ui(compose.id, 5, table + first);
    glDispatchCompute(GLuint(groups_x), rows, 1);
    ++st->compose_dispatches;
  }
  st->composed_records += records;
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // The rows before the draws read them.
}

Status extrasNeedComposing(const char* who, bool extras, uint32_t stride) {
  if (!extras || stride > 0) return Status::ok();
  return {StatusCode::kUnsupported,
          std::string(who) +
              ": 2D blends are drawn through composed layers, and these do not fit "
              "(RendererDesc::compose_layers off, or the rows past "
              "GL_MAX_SHADER_STORAGE_BLOCK_SIZE or the compute grid): draw fewer instances"};
}

void composeGpuLayers(const DrawResources& r, bool motion, uint32_t stride, uint32_t instances,
                      uint32_t extras, uint32_t previous_extras, DrawStats* st) {
  const Program& compose =
      r.programs[motion ? ProgramId::kGpuLayerComposeMotion : ProgramId::kGpuLayerCompose];
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // The cull pass's records; earlier reads.
  glUseProgram(compose.id);
  r.palette->bind();
  r.scratch->layer_compose.bind(motion);
  glProgramUniform1ui(compose.id, 5, instances);
  glProgramUniform1ui(compose.id, 6, extras);
  if (motion) glProgramUniform1ui(compose.id, 7, previous_extras);
  const uint64_t invocations = uint64_t(instances) * stride;
  // prepareComposedRows checked that the grid holds them: dispatchGroups cannot refuse.
  (void)dispatchGroups(*r.info, (invocations + 63) / 64, "composed layers");
  ++st->compose_dispatches;
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

}  // namespace si::detail
