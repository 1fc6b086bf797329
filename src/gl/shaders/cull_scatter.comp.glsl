// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling, pass 3 of 3: one thread per visible instance writes its entry into each
// worn sub-mesh's bucket, and for an entry that is pre-skinned, where its vertices go in the
// ring and which list they come from.
#include "cull_common.glsl"
#include "dispatch_index.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 12) writeonly buffer SiEntryData { uvec2 si_entry_data[]; };
void main() {
  uint v = siFlatInvocation();
  if (v >= si_visible_count) return;
  uvec4 e = si_visible[v];
  for (uint m = e.z; m != 0u; m &= m - 1u) {
    uint b = e.y * u_counts.z + uint(findLSB(m));
    uint slot = atomicAdd(si_cursor[b], 1u);
    si_entries[slot] = v;
    uint i = slot - si_bucket_offset[b];
    if (i < si_fitted[b])
      si_entry_data[slot] = uvec2(si_thread_base[b] + i * si_bucket_info[b].x, si_bucket_info[b].y);
  }
}
