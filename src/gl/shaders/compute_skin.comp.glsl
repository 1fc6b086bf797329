// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Compute pre-skinning: one thread per (instance, vertex of its LOD) of a batch, writing the
// camera-relative world position and the octahedral normal into the ring (and, for a source
// with tangents, the packed skinned tangent into the tangent ring). SI_MOTION_VECTORS:
// also the previous frame's position (siSkinPrevious) into the parallel previous ring.
// SI_LAYERS: each instance's overlay composed on its mask (siSkinLayered; with
// SI_COMPOSED_LAYERS read from the compose pass's rows, siSkinComposed).
// With SI_MOTION_VECTORS the previous records come through an index (previous_index.glsl),
// u_batch_slot the batch's first slot in that numbering.
#ifdef SI_MOTION_VECTORS
#define SI_PREVIOUS_RECORDS
#endif
#include "si_skinning.glsl"
#ifdef SI_COMPOSED_LAYERS
#define SI_COMPOSED_READ
#define SI_COMPOSED_BY_SLOT  // Each slot's composed record.
#include "layer_compose.glsl"
#endif
#define SI_SKINNED_OUT_BINDING 1
#define SI_SKINNED_PREVIOUS_OUT_BINDING 4
#include "pre_skin_common.glsl"
#include "dispatch_index.glsl"
#ifdef SI_MOTION_VECTORS
#include "previous_index.glsl"
#endif
#if defined(SI_MOTION_VECTORS) || defined(SI_COMPOSED_LAYERS)
layout(location = 7) uniform uint u_batch_slot;  // Its slots' composed records, previous indices.
#else
const uint u_batch_slot = 0u;
#endif
layout(local_size_x = 64) in;
void main() {
  uint g = siFlatInvocation();
  uint i = g / u_chunk.y;
  if (i >= u_layout.x) return;
  uint k = g - i * u_chunk.y;
  uint source = si_lod_vertices[u_chunk.z + k];
  si_pre_skin_lod = (u_layout.y >> 16) & 7u;
  uvec4 layer = siLayer(u_chunk.w + i);
  SiInstance inst = si_instances[u_chunk.w + i];
  uint slot = u_batch_slot + u_chunk.w + i;
#ifdef SI_COMPOSED_LAYERS
  uint composed = siComposedRecord(slot);
#else
  uint composed = slot;  // Unused.
#endif
  siWritePreSkinned(u_chunk.x + g, source, inst, layer, composed);
#ifdef SI_MOTION_VECTORS
  SiInstance prev = siPreviousRecord(slot, inst);
  si_previous_out[u_chunk.x + g] =
      vec4(siPreSkinPrevious(source, prev, siPreviousLayer(u_chunk.w + i), composed), 1.0);
#endif
}
