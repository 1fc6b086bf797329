// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling, pass 3 of 3: one thread per visible instance writes its entry into each
// worn sub-mesh's bucket.
#include "cull_common.glsl"
layout(local_size_x = 64) in;
void main() {
  uint v = gl_GlobalInvocationID.x;
  if (v >= si_visible_count) return;
  uvec4 e = si_visible[v];
  for (uint m = e.z; m != 0u; m &= m - 1u) {
    uint slot = atomicAdd(si_cursor[e.y * u_counts.z + uint(findLSB(m))], 1u);
    si_entries[slot] = v;
  }
}
