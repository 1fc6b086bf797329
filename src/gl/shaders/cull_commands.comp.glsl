// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling, pass 2 of 3 (one thread): prefix sums of the bucket counts into the
// indirect draw commands and the scatter pass's dispatch size.
#include "cull_common.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = 7) writeonly buffer SiCommands { uint si_commands[]; };
layout(std430, binding = 8) readonly buffer SiRanges { uvec2 si_ranges[]; };  // first, count
void main() {
  uint buckets = u_counts.y * u_counts.z, offset = 0u;
  for (uint b = 0u; b < buckets; ++b) {
    uint n = si_bucket_count[b];
    si_commands[b * 5u + 0u] = si_ranges[b].y;
    si_commands[b * 5u + 1u] = n;
    si_commands[b * 5u + 2u] = si_ranges[b].x;
    si_commands[b * 5u + 3u] = 0u;
    si_commands[b * 5u + 4u] = offset;
    si_cursor[b] = offset;
    offset += n;
  }
  si_dispatch[0] = (si_visible_count + 63u) / 64u;
  si_dispatch[1] = 1u;
  si_dispatch[2] = 1u;
}
