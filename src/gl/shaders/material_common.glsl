// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Per-vertex materials (si::MaterialTable): each mesh vertex's material index, 16 bits, two to
// a word, at storage binding 10; the table of (base colour factor, texture array layer) at
// storage binding 11. Vertex shaders pass the index flat to the fragment shader.
#ifndef SI_MATERIAL_COMMON_GLSL
#define SI_MATERIAL_COMMON_GLSL
struct SiMaterial {
  vec4 factor;
  uvec4 layer;  // x: layer of the base colour array.
};
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
