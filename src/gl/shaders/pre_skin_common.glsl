// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Compute pre-skinning, shared by the skinning pass and the vertex-pulling draw: the raw vertex
// buffer (32 or 36 bytes a vertex, read as words), the compacted vertex list of each (sub-mesh,
// LOD) and the pre-skinned ring (16 bytes a vertex: camera-relative world position, octahedral
// normal as 2 x snorm16).
// u_chunk: x first ring vertex of the draw, y vertices of the LOD, z offset into the LOD vertex
// list, w first instance of the batch; u_layout: x instances, y words per source vertex.
#ifndef SI_PRE_SKIN_COMMON_GLSL
#define SI_PRE_SKIN_COMMON_GLSL
layout(std430, binding = 2) readonly buffer SiSourceVertices { uint si_source[]; };
layout(std430, binding = 3) readonly buffer SiLodVertices { uint si_lod_vertices[]; };
layout(location = 5) uniform uvec4 u_chunk;
layout(location = 6) uniform uvec2 u_layout;
#endif
