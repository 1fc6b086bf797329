// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// One entry of a character's material table as the shaders read it (material_common.glsl's
// SiMaterial), made from si::MaterialEntry: what every back-end uploads. 64 bytes, so the
// OpenGL ES profile's block of kEsMaxMaterials entries fits the 16 KiB every ES 3.0 context has.

#include <cstdint>

#include <glm/glm.hpp>

#include "si/core/material_table.h"
#include "si/core/shader_inputs.h"

namespace si::detail {

struct GpuMaterial {
  glm::vec4 factor;    // Base colour factor.
  glm::vec4 emissive;  // rgb emissive factor, w the alpha cutoff (negative: not masked).
  glm::vec4 pbr;       // Metallic, roughness, normal scale, occlusion strength.
  glm::uvec4 layer;    // x base colour | emissive << 16 (colour layers), y normal |
                       // metallic-roughness << 16, z occlusion | flags << 16 (data layers;
                       // flag 1: double-sided), w the mesh's optional vertex words (1
                       // texture coordinates 1, 2 colours: vertexWordBits()).
};
static_assert(sizeof(GpuMaterial) == 64, "material_common.glsl's SiMaterial");

/// SiMaterial.layer.w for a mesh whose vertex stream is `stream`: 1 when it has texture
/// coordinates 1, 2 when it has colours (the fragment stage reads only those).
inline uint32_t vertexWordBits(const VertexStream& stream) {
  return (stream.texcoord1_offset != 0 ? 1u : 0u) | (stream.color_offset != 0 ? 2u : 0u);
}

/// Material `e` of a mesh whose optional vertex words are `vertex_words` (vertexWordBits()).
inline GpuMaterial gpuMaterial(const MaterialEntry& e, uint32_t vertex_words) {
  return {e.base_color_factor, glm::vec4(e.emissive_factor, e.alpha_cutoff),
          glm::vec4(e.metallic, e.roughness, e.normal_scale, e.occlusion_strength),
          glm::uvec4(e.layer | (e.emissive_layer << 16),
                     e.normal_layer | (e.metallic_roughness_layer << 16),
                     e.occlusion_layer | (uint32_t(e.double_sided ? 1 : 0) << 16), vertex_words)};
}

}  // namespace si::detail
