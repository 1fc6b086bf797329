// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Impostor quads for the instanced paths and the GPU-driven path.
#include "gl/paths/impostor_draw.h"

namespace si::detail {

namespace {

// Binds program `id`, the camera and light uniforms and the atlas (the quad reads no palette,
// vertex buffer or material; `quads_computed`: ImpostorAtlas::bind's).
void useImpostorProgram(const DrawResources& r, const PathFrame& f, ProgramId id,
                        bool quads_computed = false) {
  const Program& program = r.programs[id];
  glUseProgram(program.id);
  setCameraUniforms(program, f.camera, f.light);
  if (program.lod >= 0) glProgramUniform1ui(program.id, program.lod, f.impostor_lod);
  r.impostor->bind(program, f.camera, quads_computed);
}

}  // namespace

void drawImpostorBatches(const DrawResources& r, const PathFrame& f, bool depth_only,
                         DrawStats* st) {
  if (f.impostor_lod == 0 || r.impostor == nullptr || !r.impostor->ready()) return;
  bool bound = false;
  const ProgramId id = depth_only ? ProgramId::kImpostorDepthOnly : ProgramId::kImpostor;
  const Program& program = r.programs[id];
  for (const DrawBatch& d : *f.batches) {
    if (d.lod != f.impostor_lod || d.sub_mesh != 0) continue;
    if (!bound) {
      markPass(r, GpuPass::kDraw);  // The meshes drawn before.
      useImpostorProgram(r, f, id);
      if (depth_only) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
      bindSlotHandles(r, f);
      bound = true;
    }
    r.ring->bindBatch(f.ring_base, d);
    setBatchSlot(program, d);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(d.instance_count));
    ++st->draw_calls;
    st->triangles += uint64_t(2) * d.instance_count;
    st->instances += d.instance_count;
  }
  if (bound && depth_only) glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  if (bound) markPass(r, GpuPass::kImpostors);
}

void drawImpostorsIndirect(const DrawResources& r, const PathFrame& f, GLuint vao, GLuint quads,
                           GLintptr dispatch, GLintptr command, DrawStats* st) {
  if (f.impostor_lod == 0 || r.impostor == nullptr || !r.impostor->ready()) return;
  // Each quad once, on every compute unit: in the vertex shader its 4 vertices computed it 4
  // times on the few units that run vertex shaders.
  useImpostorProgram(r, f, ProgramId::kImpostorQuads);
  const GLuint program = r.programs[ProgramId::kImpostorQuads].id;
  glProgramUniform1ui(program, 37, f.impostor_lod * f.crowd->desc().sub_mesh_count);
  // A quad holding no pixel centre rasters nothing on a single-sampled target: left out there.
  GLint samples = 0;
  glGetIntegerv(GL_SAMPLES, &samples);
  glProgramUniform1ui(program, 38, samples > 1 ? 0u : 1u);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 15, quads);
  glDispatchComputeIndirect(dispatch);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  useImpostorProgram(
      r, f, f.depth_only ? ProgramId::kGpuDrivenImpostorDepthOnly : ProgramId::kGpuDrivenImpostor,
      true);
  glBindVertexArray(vao);
  if (f.depth_only) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glDrawArraysIndirect(GL_TRIANGLE_STRIP, reinterpret_cast<const void*>(command));
  if (f.depth_only) glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  ++st->draw_calls;
  markPass(r, GpuPass::kImpostors);
}

}  // namespace si::detail
