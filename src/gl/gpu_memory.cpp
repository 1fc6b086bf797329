// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Renderer::gpuMemory: every buffer and texture the renderer made, by what holds it, at the sizes
// the driver reports.
#include <glad/gl.h>

#include "gl/host_errors.h"
#include "gl/renderer_impl.h"
#include "gl/resources/gl_allocation.h"
#include "si/gl/renderer.h"

namespace si {

Status Renderer::gpuMemory(GpuMemory* out) const {
  if (!impl_ || out == nullptr)
    return {StatusCode::kInvalidArgument, "gpuMemory: init() first, non-null output"};
  const Impl& m = *impl_;
  Status s = m.esRefuses("gpuMemory", "texture size queries");
  if (!s.isOk()) return s;
  detail::takeHostErrors("gpuMemory");
  using detail::bufferBytes;
  using detail::textureBytes;
  GpuMemory g;
  g.record_ring_bytes = bufferBytes(m.ring.buffer());
  const detail::ScratchBuffers& sc = m.scratch;
  for (const detail::VertexRing* r :
       {&sc.compute_ring, &sc.compute_previous_ring, &sc.gpu_driven_ring,
        &sc.gpu_driven_previous_ring, &sc.compute_tangent_ring, &sc.gpu_driven_tangent_ring})
    g.vertex_ring_bytes += bufferBytes(r->buffer);
  g.vertex_ring_bytes += bufferBytes(sc.cpu_stream);
  g.staging_bytes = sc.uploads.bytes();
  g.other_shared_bytes = bufferBytes(sc.mask_table.buffer) +
                         bufferBytes(sc.layer_compose.table.buffer) +
                         bufferBytes(sc.layer_compose.rows[0]) +
                         bufferBytes(sc.layer_compose.rows[1]) + m.traditional_path.gpuBytes();
  for (const std::unique_ptr<detail::CharacterSlot>& c : m.characters) {
    CharacterGpuMemory k;
    const detail::CharacterBuffers& b = c->character;
    k.character_bytes = c->palette.gpuBytes() + bufferBytes(b.vertex_buffer) +
                        bufferBytes(b.index_buffer) + textureBytes(b.base_texture) +
                        textureBytes(b.data_texture) + bufferBytes(b.vertex_materials) +
                        bufferBytes(b.material_table) + bufferBytes(c->preskin.index_buffer) +
                        bufferBytes(c->preskin.lod_vertex_list) +
                        textureBytes(c->impostor.texture) + bufferBytes(c->impostor.clips);
    c->gpu_culled.memory(&k.crowds);
    g.characters.push_back(std::move(k));
  }
  *out = std::move(g);
  return checkGlErrors("gpuMemory");
}

}  // namespace si
