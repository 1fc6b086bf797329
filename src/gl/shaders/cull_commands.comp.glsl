// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling, pass 2 of 3 (one thread): prefix sums of the bucket counts into the
// indirect draw commands and the scatter pass's dispatch size; and the pre-skinning split: in
// bucket order, as many of each bucket's instances as the ring still holds are pre-skinned
// (commands 256 and up, drawn by vertex pulling), the rest drawn with vertex-shader skinning
// (commands 0 to 255). u_ring_vertices 0 pre-skins nothing. The impostor bucket's instances
// (its range is empty) are also drawn as quads: a glDrawArraysIndirect command after the
// others (word 2560; its instance count the impostor quads pass's), and that pass's dispatch
// (impostor_quads.comp.glsl).
#include "cull_common.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = 7) writeonly buffer SiCommands { uint si_commands[]; };
layout(std430, binding = 8) readonly buffer SiRanges { uvec2 si_ranges[]; };  // first, count
layout(location = 19) uniform uint u_ring_vertices;
// GL_MAX_COMPUTE_WORK_GROUP_COUNT's x (GlInfo::max_compute_groups_x): the later passes' groups
// are laid out in rows of at most this many (src/gl/paths/dispatch_grid.h).
layout(location = 27) uniform uint u_max_groups_x;
// The impostor level's bucket (CrowdDesc::impostor_lod x sub-meshes); past the buckets: none.
layout(location = 37) uniform uint u_impostor_bucket;
// A later pass's groups for `threads` threads of 64-wide groups, in rows of at most
// u_max_groups_x (x, y, z).
uvec3 siRowsOfGroups(uint threads) {
  uint groups = max((threads + 63u) / 64u, 1u);
  return uvec3(min(groups, u_max_groups_x), (groups + u_max_groups_x - 1u) / u_max_groups_x, 1u);
}
void main() {
  uint buckets = u_counts.y * u_counts.z, offset = 0u, threads = 0u;
  for (uint b = 0u; b < buckets; ++b) {
    uint n = si_bucket_count[b];
    uvec4 info = si_bucket_info[b];
    uint fit = 0u;
    if (info.x > 0u && u_ring_vertices > threads) fit = min(n, (u_ring_vertices - threads) / info.x);
    si_commands[b * 5u + 0u] = si_ranges[b].y;  // Vertex-shader skinning: the rest.
    si_commands[b * 5u + 1u] = n - fit;
    si_commands[b * 5u + 2u] = si_ranges[b].x;
    si_commands[b * 5u + 3u] = 0u;
    si_commands[b * 5u + 4u] = offset + fit;
    uint p = (256u + b) * 5u;                  // Pre-skinned: the first `fit`.
    si_commands[p + 0u] = info.w;
    si_commands[p + 1u] = fit;
    si_commands[p + 2u] = info.z;
    si_commands[p + 3u] = 0u;
    si_commands[p + 4u] = offset;
    si_cursor[b] = offset;
    si_bucket_offset[b] = offset;
    si_thread_base[b] = threads;
    si_fitted[b] = fit;
    offset += n;
    threads += fit * info.x;
  }
  si_thread_base[buckets] = threads;
  bool impostors = u_impostor_bucket < buckets;
  si_commands[2560u] = 4u;
  si_commands[2561u] = 0u;  // The impostor quads pass counts the quads it keeps.
  si_commands[2562u] = 0u;
  si_commands[2563u] = 0u;
  uint quads = impostors ? si_bucket_count[u_impostor_bucket] : 0u;
  uvec3 g = siRowsOfGroups(quads);
  si_impostor_dispatch = uint[4](g.x, g.y, g.z, quads);
  si_impostors_drawn = 0u;
  g = siRowsOfGroups(si_visible_count);
  si_dispatch[0] = g.x;
  si_dispatch[1] = g.y;
  si_dispatch[2] = g.z;
  g = siRowsOfGroups(threads);
  si_skin_dispatch = uint[4](g.x, g.y, g.z, threads);
}
