// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// One instanced draw per batch (B. Dudash, "Skinned Instancing", NVIDIA 2007).
#include "gl/paths/vertex_shader_path.h"

#include "gl/paths/impostor_draw.h"
#include "gl/paths/layer_compose_pass.h"

namespace si::detail {

Status VertexShaderPath::draw(const DrawResources& r, const PathFrame& f, DrawStats* st) {
  const bool depth_only = f.program == ProgramId::kDepthOnly ||
                          f.program == ProgramId::kDepthOnlyLayers ||
                          f.program == ProgramId::kDepthOnlyComposed;
  if (f.composed) {
    composeLayers(r, f, st);
    markPass(r, GpuPass::kCompose);
  }
  const Program& program = r.programs[f.program];
  bindShading(r, program, f.camera, f.light);
  setMotionUniforms(program, f);
  if (f.motion) bindPreviousRecords(r, program, f);
  bindSlotHandles(r, f);
  if (depth_only) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  for (const DrawBatch& d : *f.batches) {
    const IndexRange range = r.character->drawnRange(d.sub_mesh, d.lod);
    if (range.index_count == 0) continue;
    r.ring->bindBatch(f.ring_base, d);
    if (f.layers) r.ring->bindLayers(f.layer_base, d);
    if (f.layers && f.motion) r.ring->bindLayers(f.previous_layer_base, d, 3);
    setBatchSlot(program, d);
    if (program.lod >= 0) glProgramUniform1ui(program.id, program.lod, d.lod);
    glDrawElementsInstanced(GL_TRIANGLES, GLsizei(range.index_count), GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(uintptr_t(range.first_index) * 4),
                            GLsizei(d.instance_count));
    ++st->draw_calls;
    st->triangles += uint64_t(range.index_count / 3) * d.instance_count;
    st->instances += d.instance_count;
  }
  if (depth_only) glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  drawImpostorBatches(r, f, depth_only, st);
  return Status::ok();
}

}  // namespace si::detail
