// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The CPU-skinning baseline: positions, normals and (u_tangents 1) tangents arrive skinned, in
// camera-relative world space; u_base_vertex is the draw's base vertex (mesh vertex =
// gl_VertexID - u_base_vertex).
#define SI_VERTEX_MATERIALS
#include "material_common.glsl"
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_texcoord;
layout(location = 3) in vec4 a_tangent;  // Read only with u_tangents 1.
#include "vertex_words.glsl"
#define SI_INSTANCE_HANDLE_UNIFORM
#include "instance_handle.glsl"
layout(location = 1) uniform mat4 u_view_projection;
layout(location = 4) uniform uint u_color;
layout(location = 5) uniform int u_base_vertex;
layout(location = 6) uniform uint u_tangents;  // 1: the stream carries tangents.
uniform uint u_lod;  // The instance's LOD (SiSurface.lod).
SI_VARYING_LAYOUT(0) out vec3 v_position;  // Camera-relative world position (SiSurface.position).
SI_VARYING_LAYOUT(1) out vec3 v_normal;
SI_VARYING_LAYOUT(2) out vec4 v_tangent;  // vec4(0) without tangents: no tangent frame.
SI_VARYING_LAYOUT(3) out vec2 v_texcoord;
SI_VARYING_LAYOUT(4) flat out uint v_color;
SI_VARYING_LAYOUT(5) flat out uint v_material;
SI_VARYING_LAYOUT(6) flat out uint v_lod;
void main() {
  v_material = siVertexMaterial(uint(gl_VertexID - u_base_vertex));
  v_normal = a_normal;
  v_texcoord = a_texcoord;
  siPassVertexWords();
  v_color = u_color;
#ifdef SI_INSTANCE_HANDLE
  v_instance_handle = u_instance_handle;
#endif
  v_lod = u_lod;
  v_tangent = u_tangents != 0u ? a_tangent : vec4(0.0);
  v_position = a_position;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
}
