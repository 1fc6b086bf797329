// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Compute pre-skinning: one thread per (instance, vertex of its LOD) of a batch, writing the
// camera-relative world position and the octahedral normal into the ring.
#include "si_skinning.glsl"
#include "pre_skin_common.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 1) writeonly buffer SiSkinnedOut { vec4 si_skinned_out[]; };
vec2 siOctEncode(vec3 n) {
  n /= abs(n.x) + abs(n.y) + abs(n.z);
  vec2 e = n.xy;
  if (n.z < 0.0) e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return e;
}
void main() {
  uint g = gl_GlobalInvocationID.x;
  uint i = g / u_chunk.y;
  if (i >= u_layout.x) return;
  uint k = g - i * u_chunk.y;
  uint base = si_lod_vertices[u_chunk.z + k] * u_layout.y;
  vec3 p = vec3(uintBitsToFloat(si_source[base]), uintBitsToFloat(si_source[base + 1u]),
                uintBitsToFloat(si_source[base + 2u]));
  int normal_bits = int(si_source[base + 3u]);
  // GL_INT_2_10_10_10_REV, normalized: what the vertex-shader path's attribute fetch computes.
  vec3 n = max(vec3(bitfieldExtract(normal_bits, 0, 10), bitfieldExtract(normal_bits, 10, 10),
                    bitfieldExtract(normal_bits, 20, 10)) / 511.0, vec3(-1.0));
  uvec4 joints;
  vec4 weights;
  if (u_layout.y == 8u) {
    joints = uvec4(unpackUnorm4x8(si_source[base + 5u]) * 255.0 + 0.5);
    weights = vec4(unpackUnorm2x16(si_source[base + 6u]), unpackUnorm2x16(si_source[base + 7u]));
  } else {
    uint j01 = si_source[base + 5u], j23 = si_source[base + 6u];
    joints = uvec4(j01 & 0xFFFFu, j01 >> 16, j23 & 0xFFFFu, j23 >> 16);
    weights = vec4(unpackUnorm2x16(si_source[base + 7u]), unpackUnorm2x16(si_source[base + 8u]));
  }
  SiInstance inst = si_instances[u_chunk.w + i];
  vec4 m0, m1, m2;
  siSkin(inst, joints, weights, m0, m1, m2);
  vec4 w0 = inst.world_rows[0], w1 = inst.world_rows[1], w2 = inst.world_rows[2];
  vec3 world = siTransformPoint(w0, w1, w2, siTransformPoint(m0, m1, m2, p));
  vec3 normal = siTransformNormal(w0, w1, w2, siTransformNormal(m0, m1, m2, n));
  si_skinned_out[u_chunk.x + g] = vec4(world, uintBitsToFloat(packSnorm2x16(siOctEncode(normal))));
}
