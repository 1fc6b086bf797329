// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Compute pre-skinning: one thread per (instance, vertex of its LOD) of a batch, writing the
// camera-relative world position and the octahedral normal into the ring.
#include "si_skinning.glsl"
#include "pre_skin_common.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 1) writeonly buffer SiSkinnedOut { vec4 si_skinned_out[]; };
void main() {
  uint g = gl_GlobalInvocationID.x;
  uint i = g / u_chunk.y;
  if (i >= u_layout.x) return;
  uint k = g - i * u_chunk.y;
  si_skinned_out[u_chunk.x + g] =
      siPreSkin(si_lod_vertices[u_chunk.z + k], si_instances[u_chunk.w + i]);
}
