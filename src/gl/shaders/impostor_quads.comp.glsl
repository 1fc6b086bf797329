// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's impostor quads pass, after the scatter pass: one thread per instance of
// the impostor bucket computes its quad (impostor_quad.glsl) once, and writes it packed, 48
// bytes, at its place in the bucket; the impostor draw's vertex shader reads it by
// gl_InstanceID (impostor.vert.glsl). Dispatched indirectly: the command pass writes the groups
// and the count (si_impostor_dispatch).
#include "cull_counters.glsl"
#include "dispatch_index.glsl"
#include "impostor_quad.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 4) readonly buffer SiRecords { SiInstance si_records[]; };
layout(std430, binding = 5) readonly buffer SiEntries { uint si_entries[]; };
layout(std430, binding = 15) writeonly buffer SiImpostorQuads { uvec4 si_impostor_quads[]; };
// The impostor level's bucket (CrowdDesc::impostor_lod x sub-meshes).
layout(location = 37) uniform uint u_impostor_bucket;
void main() {
  uint i = siFlatInvocation();
  if (i >= si_impostor_dispatch[3]) return;
  SiImpostorQuad q = siImpostorQuad(si_records[si_entries[si_bucket_offset[u_impostor_bucket] + i]]);
  uvec4 w0, w1, w2;
  siPackImpostorQuad(q, w0, w1, w2);
  si_impostor_quads[3u * i] = w0;
  si_impostor_quads[3u * i + 1u] = w1;
  si_impostor_quads[3u * i + 2u] = w2;
}
