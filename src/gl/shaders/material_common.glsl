// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Per-vertex materials (si::MaterialTable): each mesh vertex's material index, 16 bits, two to
// a word, at storage binding 10; the table of metallic-roughness entries at storage binding 11. Vertex shaders pass the index flat to the fragment shader. GLSL ES 3.00
// has no storage buffers: there the same index buffer is vertex attribute 6 (16 bits a vertex)
// and the table a uniform block of SI_MAX_MATERIALS entries (std140 lays them out as std430
// does), bound at uniform binding 11.
#ifndef SI_MATERIAL_COMMON_GLSL
#define SI_MATERIAL_COMMON_GLSL
#include "si_profile.glsl"
struct SiMaterial {
  vec4 factor;    // Base colour factor.
  vec4 emissive;  // rgb emissive factor; w the alpha cutoff (negative: not masked).
  vec4 pbr;       // Metallic, roughness, normal scale, occlusion strength.
  // x base colour layer | emissive layer << 16 (colour array), y normal | metallic-roughness
  // << 16, z occlusion | flags << 16 (data array; flag 1 double-sided); 0xFFFF: none; w the
  // mesh's optional vertex words (the same in every entry of a character): 1 texture
  // coordinates 1, 2 colours (without them the vertex stage's outputs for them go unread).
  uvec4 layer;
};
#if defined(GL_ES) && __VERSION__ < 310
#ifdef SI_VERTEX_MATERIALS
layout(location = 6) in uint a_material;
uint siVertexMaterial(uint vertex) { return a_material; }
#endif
#ifdef SI_MATERIAL_TABLE
layout(std140) uniform SiMaterials { SiMaterial si_materials[SI_MAX_MATERIALS]; };
#endif
#else
#ifdef SI_VERTEX_MATERIALS
layout(std430, binding = 10) readonly buffer SiVertexMaterials { uint si_vertex_materials[]; };
uint siVertexMaterial(uint vertex) {
  return (si_vertex_materials[vertex >> 1] >> ((vertex & 1u) * 16u)) & 0xFFFFu;
}
#endif
#ifdef SI_MATERIAL_TABLE
layout(std430, binding = 11) readonly buffer SiMaterials { SiMaterial si_materials[]; };
#endif
#endif
#endif
