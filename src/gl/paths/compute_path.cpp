// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Compute pre-skinning into a bounded ring, drawn by vertex pulling.
#include "gl/paths/compute_path.h"

#include <algorithm>

#include "core/str_cat.h"
#include "gl/paths/impostor_draw.h"
#include "gl/paths/layer_compose_pass.h"
#include "gl/resources/gl_allocation.h"

namespace si::detail {

void bindPreSkinning(const DrawResources& r, GLuint out, GLuint vertex_list, GLuint tangents) {
  r.palette->bind();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, r.character->vertex_buffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, vertex_list);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 28, tangents != kNoObject ? tangents : out);
}

Status ComputePath::prepare(const DrawResources& r) {
  if (vao_ != kNoObject) glDeleteVertexArrays(1, &vao_);
  glCreateVertexArrays(1, &vao_);
  glVertexArrayElementBuffer(vao_, r.preskin->index_buffer);
  return Status::ok();
}

Status ComputePath::ensureRing(const DrawResources& r) {
  const uint64_t bytes =
      r.desc->compute_ring_bytes == 0 ? uint64_t(32) << 20 : r.desc->compute_ring_bytes;
  Status s =
      r.scratch->compute_ring.ensure(std::max<uint64_t>(bytes / 16, r.preskin->max_lod_vertices),
                                     false, "compute pre-skinning: the pre-skinned vertex ring");
  if (s.isOk() && r.preskin->tangents)
    s = r.scratch->compute_tangent_ring.ensure(r.scratch->compute_ring.vertices, true,
                                               "compute pre-skinning: the tangent ring");
  return s;
}

// For each batch, a compute dispatch skins its instances' vertices into the ring; when the ring
// is full (or at the end) the pending draws read them by vertex id. Barriers order the writes
// before the draws and the draws before the ring is overwritten.
Status ComputePath::draw(const DrawResources& r, const PathFrame& f, DrawStats* st) {
  Status s = ensureRing(r);
  if (!s.isOk()) return s;
  const PreSkinLists& lists = *r.preskin;
  const Program& skin = r.programs[preSkinningProgram(false, f.motion, f.layers, f.composed)];
  // Masked joints once a record (layer_compose_pass.h).
  if (f.composed) {
    composeLayers(r, f, st);
    markPass(r, GpuPass::kCompose);
  }
  const Program& pulled = r.programs[pullingProgram(false, f.motion, lists.tangents)];
  if (f.motion) {
    s = r.scratch->compute_previous_ring.ensure(r.scratch->compute_ring.vertices, true,
                                                "motion vectors: the previous position ring");
    if (!s.isOk()) return s;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, r.scratch->compute_previous_ring.buffer);
    setMotionUniforms(pulled, f);
    bindPreviousRecords(r, skin, f);
  }
  const GLuint ring = r.scratch->compute_ring.buffer;
  const uint64_t ring_vertices = r.scratch->compute_ring.vertices;
  bindPreSkinning(r, ring, lists.lod_vertex_list,
                  lists.tangents ? r.scratch->compute_tangent_ring.buffer : kNoObject);
  bindAppearance(r, pulled);
  bindSlotHandles(r, f);
  setCameraUniforms(pulled, f.camera, f.light);
  glBindVertexArray(vao_);
  // A dispatch's groups go in rows (dispatchGroups): only the ring bounds a chunk.
  uint64_t cursor = 0;
  pending_.clear();
  const auto flush = [&] {
    if (pending_.empty()) return;
    markPass(r, GpuPass::kSkin);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // Skinned vertices before the draws.
    glUseProgram(pulled.id);
    for (const PendingDraw& p : pending_) {
      r.ring->bindBatch(f.ring_base, p.batch);
      glProgramUniform4ui(pulled.id, 5, p.ring_first, p.lod.vertex_count, p.lod.vertex_offset,
                          p.first_instance);
      glProgramUniform2ui(pulled.id, 6, p.instances, lists.drawLayout());
      setBatchSlot(pulled, p.batch);
      if (pulled.lod >= 0) glProgramUniform1ui(pulled.id, pulled.lod, p.batch.lod);
      glDrawElementsInstanced(GL_TRIANGLES, GLsizei(p.lod.index_count), GL_UNSIGNED_INT,
                              reinterpret_cast<const void*>(uintptr_t(p.lod.first_index) * 4),
                              GLsizei(p.instances));
      ++st->draw_calls;
      st->triangles += uint64_t(p.lod.index_count / 3) * p.instances;
      st->instances += p.instances;
    }
    markPass(r, GpuPass::kDraw);
    st->ring_bytes_used = std::max<uint64_t>(st->ring_bytes_used, cursor * 16);
    ++st->compute_chunks;
    pending_.clear();
    cursor = 0;
  };
  for (const DrawBatch& d : *f.batches) {
    if (d.sub_mesh >= lists.lods.size()) continue;
    const PreSkinLists::Lod& l = lists.lod(d.sub_mesh, d.lod);
    if (l.vertex_count == 0 || l.index_count == 0) continue;
    for (uint32_t first = 0; first < d.instance_count;) {
      const uint64_t fit = (ring_vertices - cursor) / l.vertex_count;
      if (fit == 0) {
        if (pending_.empty())  // The whole ring does not hold one instance: refuse, never loop.
          return {StatusCode::kLimitExceeded,
                  strCat("compute pre-skinning: the ring of ", ring_vertices,
                         " vertices does not hold one instance of a LOD of ", l.vertex_count,
                         " vertices")};
        flush();
        continue;
      }
      const uint32_t count = uint32_t(std::min<uint64_t>(d.instance_count - first, fit));
      if (pending_.empty()) {
        // The last chunk's draws (or last frame's) are done reading the ring.
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glUseProgram(skin.id);
      }
      r.ring->bindBatch(f.ring_base, d);
      setBatchSlot(skin, d);  // Where its previous indices and composed records start.
      if (f.layers) r.ring->bindLayers(f.layer_base, d);
      if (f.layers && f.motion) r.ring->bindLayers(f.previous_layer_base, d, 3);
      glProgramUniform4ui(skin.id, 5, uint32_t(cursor), l.vertex_count, l.vertex_offset, first);
      glProgramUniform2ui(skin.id, 6, count,
                          lists.drawLayout() | (d.lod << 16));  // LOD: morph cut.
      const uint64_t threads = uint64_t(count) * l.vertex_count;
      s = dispatchGroups(*r.info, (threads + 63) / 64, "compute pre-skinning");
      if (!s.isOk()) return s;
      pending_.push_back({d, l, first, count, uint32_t(cursor)});
      ++st->compute_dispatches;
      st->skinned_vertices += threads;
      cursor += threads;
      first += count;
    }
  }
  flush();
  drawImpostorBatches(r, f, false, st);
  return Status::ok();
}

void ComputePath::release() {
  if (vao_ != kNoObject) glDeleteVertexArrays(1, &vao_);
  vao_ = kNoObject;
}

}  // namespace si::detail
