// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's impostor quads pass, after the scatter pass: one thread per instance of
// the impostor bucket computes its quad (impostor_quad.glsl) once and, where the quad can
// cover a pixel's centre, appends it packed (64 bytes) and counts it in the impostor draw's
// instance count; the draw's vertex shader reads it by gl_InstanceID (impostor.vert.glsl). A
// quad whose screen rectangle holds no pixel centre would raster no fragment: it is left out,
// and its 4 vertices with it (u_small_quads 1; 0 for a multisampled target, whose samples lie
// off the centres). Dispatched indirectly: the command pass writes the groups and the count
// (si_impostor_dispatch).
#include "cull_counters.glsl"
#include "dispatch_index.glsl"
#include "impostor_quad.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 4) readonly buffer SiRecords { SiInstance si_records[]; };
layout(std430, binding = 5) readonly buffer SiEntries { uint si_entries[]; };
layout(std430, binding = 6) readonly buffer SiVisible { uvec4 si_visible[]; };  // w: handle
layout(std430, binding = 7) buffer SiCommands { uint si_commands[]; };
layout(std430, binding = 15) writeonly buffer SiImpostorQuads { uvec4 si_impostor_quads[]; };
// The impostor level's bucket (CrowdDesc::impostor_lod x sub-meshes).
layout(location = 37) uniform uint u_impostor_bucket;
// 1: quads that hold no pixel centre are left out (a single-sampled target).
layout(location = 38) uniform uint u_small_quads;
shared uint s_kept, s_base;

// Whether quad `q` may cover a pixel centre of the viewport (half its size: u_impostor_texels):
// its corners' screen rectangle, widened by a hundredth of a pixel against rounding, holds one
// (pixel centres at integers plus a half). A corner at or behind the eye keeps it.
bool siMayCoverACentre(SiImpostorQuad q) {
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  for (uint k = 0u; k < 4u; ++k) {
    vec2 corner = mix(q.rect.xy, q.rect.zw, vec2(float(k & 1u), float(k >> 1)));
    vec4 c = u_view_projection *
             vec4(q.centre + (corner.x - 0.5) * q.right + (corner.y - 0.5) * q.up, 1.0);
    if (!(c.w > 0.0)) return true;
    vec2 pixel = (c.xy / c.w + 1.0) * u_impostor_texels.xy;
    lo = min(lo, pixel);
    hi = max(hi, pixel);
  }
  bvec2 holds = greaterThanEqual(floor(hi - 0.5 + 0.01), ceil(lo - 0.5 - 0.01));
  return holds.x && holds.y;
}

void main() {
  if (gl_LocalInvocationIndex == 0u) s_kept = 0u;
  barrier();
  uint i = siFlatInvocation();
  bool keep = false;
  uint at = 0u, handle = 0u;
  SiImpostorQuad q;
  if (i < si_impostor_dispatch[3]) {
    uint entry = si_entries[si_bucket_offset[u_impostor_bucket] + i];
    q = siImpostorQuad(si_records[entry]);
    handle = si_visible[entry].w;
    keep = u_small_quads == 0u || siMayCoverACentre(q);
    if (keep) at = atomicAdd(s_kept, 1u);
  }
  barrier();
  // One append per group: the draw command's instance count (word 2561), and the count the
  // draw's statistics read back.
  if (gl_LocalInvocationIndex == 0u && s_kept > 0u) {
    s_base = atomicAdd(si_commands[2561u], s_kept);
    atomicAdd(si_impostors_drawn, s_kept);
  }
  barrier();
  if (!keep) return;
  uvec4 w0, w1, w2;
  siPackImpostorQuad(q, w0, w1, w2);
  uint o = 4u * (s_base + at);
  si_impostor_quads[o] = w0;
  si_impostor_quads[o + 1u] = w1;
  si_impostor_quads[o + 2u] = w2;
  si_impostor_quads[o + 3u] = uvec4(handle, 0u, 0u, 0u);
}
