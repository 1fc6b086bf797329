// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Compute pre-skinning's draw: pulls the pre-skinned vertex of (gl_InstanceID, gl_VertexID)
// from the ring; texture coordinates from the source vertex.
#include "si_skinning.glsl"
#include "pre_skin_common.glsl"
layout(std430, binding = 1) readonly buffer SiSkinned { vec4 si_skinned[]; };
layout(location = 1) uniform mat4 u_view_projection;
out vec3 v_normal;
out vec2 v_texcoord;
flat out uint v_color;
vec3 siOctDecode(vec2 e) {
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}
void main() {
  uint k = uint(gl_VertexID);
  vec4 s = si_skinned[u_chunk.x + uint(gl_InstanceID) * u_chunk.y + k];
  uint base = si_lod_vertices[u_chunk.z + k] * u_layout.y;
  v_texcoord = unpackHalf2x16(si_source[base + 4u]);
  v_normal = siOctDecode(unpackSnorm2x16(floatBitsToUint(s.w)));
  v_color = si_instances[u_chunk.w + uint(gl_InstanceID)].blend.w;
  gl_Position = u_view_projection * vec4(s.xyz, 1.0);
}
