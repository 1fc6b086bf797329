// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Compute pre-skinning: one thread per (instance, vertex of its LOD) of a batch, writing the
// camera-relative world position and the octahedral normal into the ring. SI_MOTION_VECTORS:
// also the previous frame's position (siSkinPrevious) into the parallel previous ring.
// SI_LAYERS: each instance's overlay composed on its mask (siSkinLayered).
#ifdef SI_MOTION_VECTORS
#define SI_PREVIOUS_RECORDS
#endif
#include "si_skinning.glsl"
#include "pre_skin_common.glsl"
#include "dispatch_index.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 1) writeonly buffer SiSkinnedOut { vec4 si_skinned_out[]; };
#ifdef SI_MOTION_VECTORS
layout(std430, binding = 4) writeonly buffer SiSkinnedPreviousOut { vec4 si_previous_out[]; };
#endif
void main() {
  uint g = siFlatInvocation();
  uint i = g / u_chunk.y;
  if (i >= u_layout.x) return;
  uint k = g - i * u_chunk.y;
  uint source = si_lod_vertices[u_chunk.z + k];
#ifdef SI_LAYERS
  uvec4 layer = si_layers[u_chunk.w + i];
#else
  uvec4 layer = uvec4(0u);
#endif
  si_skinned_out[u_chunk.x + g] = siPreSkin(source, si_instances[u_chunk.w + i], layer);
#ifdef SI_MOTION_VECTORS
  si_previous_out[u_chunk.x + g] = vec4(siPreSkinPrevious(source, u_chunk.w + i), 1.0);
#endif
}
