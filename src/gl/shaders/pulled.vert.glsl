// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Pre-skinning's draw: pulls the pre-skinned vertex of (instance, gl_VertexID) from the ring
// (SI_TANGENTS, for a character with tangents: its skinned tangent from the tangent ring at the
// same slot; without, the tangent output is the constant "none", which costs no varying);
// texture coordinates from the source vertex (SI_VERTEX_WORDS, for a mesh with texture
// coordinates 1 or colours: those too).
// SI_GPU_DRIVEN: the instance is a bucket entry (a_entry = baseInstance + gl_InstanceID, an
// identity buffer with divisor 1) whose ring base and list offset the GPU-driven passes wrote;
// otherwise the batch's u_chunk says where its instances are. SI_MOTION_VECTORS: the clip
// positions of the vertex and of its previous position (the previous ring, at the same slot)
// under the last two frames' cameras, for the fragment shader's motion output.
// SI_INSTANCE_HANDLE: also the instance's handle (instance_handle.glsl).
#ifdef SI_GPU_DRIVEN
#define SI_SOURCE_BINDING 14
#define SI_LOD_VERTICES_BINDING 15
#endif
#include "si_skinning.glsl"
#include "pre_skin_common.glsl"
#define SI_VERTEX_MATERIALS
#include "material_common.glsl"
#ifdef SI_GPU_DRIVEN
layout(std430, binding = 13) readonly buffer SiSkinned { vec4 si_skinned[]; };
layout(location = 5) in uint a_entry;
layout(std430, binding = 4) readonly buffer SiRecords { SiInstance si_records[]; };
layout(std430, binding = 5) readonly buffer SiEntries { uint si_entries[]; };
layout(std430, binding = 12) readonly buffer SiEntryData { uvec2 si_entry_data[]; };  // ring, list
// The cull pass's visible list: x dense index, y LOD, z worn mask, w handle (cull_common.glsl).
layout(std430, binding = 6) readonly buffer SiVisible { uvec4 si_visible[]; };
#else
uniform uint u_lod;  // The batch's LOD (SiSurface.lod).
layout(std430, binding = 1) readonly buffer SiSkinned { vec4 si_skinned[]; };
#endif
#ifdef SI_TANGENTS
layout(std430, binding = 28) readonly buffer SiTangents { uint si_tangents[]; };
#endif
#ifdef SI_MOTION_VECTORS
#ifdef SI_GPU_DRIVEN
#define SI_PREVIOUS_RING_BINDING 22
#else
#define SI_PREVIOUS_RING_BINDING 4
#endif
layout(std430, binding = SI_PREVIOUS_RING_BINDING) readonly buffer SiSkinnedPrevious {
  vec4 si_skinned_previous[];
};
uniform mat4 u_motion_view_projection;
uniform mat4 u_previous_view_projection;
SI_VARYING_LAYOUT(7) out vec4 v_motion_current;
SI_VARYING_LAYOUT(8) out vec4 v_motion_previous;
#endif
#include "instance_handle.glsl"
layout(location = 1) uniform mat4 u_view_projection;
SI_VARYING_LAYOUT(0) out vec3 v_position;  // Camera-relative world position (SiSurface.position).
SI_VARYING_LAYOUT(1) out vec3 v_normal;
SI_VARYING_LAYOUT(2) out vec4 v_tangent;  // vec4(0) without tangents: no tangent frame.
SI_VARYING_LAYOUT(3) out vec2 v_texcoord;
#ifdef SI_VERTEX_WORDS
SI_VARYING_LAYOUT(9) out vec2 v_texcoord1;     // vec2(0) where the mesh has none.
SI_VARYING_LAYOUT(10) out vec4 v_vertex_color;  // vec4(1) where the mesh has none.
#endif
SI_VARYING_LAYOUT(4) flat out uint v_color;
SI_VARYING_LAYOUT(5) flat out uint v_material;
SI_VARYING_LAYOUT(6) flat out uint v_lod;
void main() {
  uint k = uint(gl_VertexID);
#ifdef SI_GPU_DRIVEN
  uvec2 at = si_entry_data[a_entry];
  uint ring = at.x + k, list = at.y;
  uint slot = si_entries[a_entry];  // The visible index.
  v_color = si_records[slot].blend.w;
  v_lod = si_visible[slot].y;
#ifdef SI_INSTANCE_HANDLE
  v_instance_handle = si_visible[slot].w;
#endif
#else
  uint ring = u_chunk.x + uint(gl_InstanceID) * u_chunk.y + k, list = u_chunk.z;
  v_color = si_instances[u_chunk.w + uint(gl_InstanceID)].blend.w;
  v_lod = u_lod;
#ifdef SI_INSTANCE_HANDLE  // u_chunk.w: the chunk's first place in its batch.
  v_instance_handle = siSlotHandle(u_chunk.w + uint(gl_InstanceID));
#endif
#endif
  vec4 s = si_skinned[ring];
#ifdef SI_MOTION_VECTORS
  v_motion_current = u_motion_view_projection * vec4(s.xyz, 1.0);
  v_motion_previous = u_previous_view_projection * vec4(si_skinned_previous[ring].xyz, 1.0);
#endif
  uint source = si_lod_vertices[list + k];
  v_texcoord = siSourceTexcoord(list, k);
#ifdef SI_VERTEX_WORDS
  v_texcoord1 = siSourceTexcoord1(source);
  v_vertex_color = siSourceColor(source);
#endif
  v_material = siVertexMaterial(source);
#ifdef SI_TANGENTS
  v_tangent = siUnpackTangent(si_tangents[ring]);
#else
  v_tangent = vec4(0.0);
#endif
  v_position = s.xyz;
  v_normal = siOctDecode(unpackSnorm2x16(floatBitsToUint(s.w)));
  gl_Position = u_view_projection * vec4(s.xyz, 1.0);
}
