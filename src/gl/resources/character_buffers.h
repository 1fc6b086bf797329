// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The character on the GPU: the vertex stream (si/core/shader_inputs.h) and index buffer, the
// vertex array that describes them, every sub-mesh's LOD ranges, and its materials (the
// si::MaterialTable: per-vertex material indices, the table, the base colour texture array).

#include <array>

#include <glad/gl.h>

#include <glm/glm.hpp>
#include <vector>

#include "gl/programs/program_set.h"
#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/core/shader_inputs.h"

namespace si {
struct MaterialTable;
struct VertexStream;
}  // namespace si

namespace si::detail {

struct CharacterBuffers {
  /// Uploads `character` for `palette` (the palette baked for it). Fails, keeping what was
  /// uploaded before, with kInvalidArgument for an invalid mesh, a palette of another skeleton
  /// or a vertex weighted to a joint the palette does not store.
  /// Base colour layers are at most `max_texture_size` texels a side (0: 2048); the morph
  /// targets' LOD cuts are `morph_lod_share` of each level's error (si::morphLodCuts).
  Status upload(const Character& character, const BakedPalette& palette, uint32_t max_texture_size,
                float morph_lod_share = 0.0f);
  void release();
  bool ready() const { return vao != kNoObject; }
  /// upload()'s materials: the per-vertex material indices and the table of `table` (its data
  /// layers given one flat layer when it has none), the colour and data texture arrays, and
  /// the faces and alpha flags; `stream` says which vertex words the materials read.
  Status uploadMaterials(MaterialTable* table, const VertexStream& stream);

  /// Sets the vertex format (attributes 0-4 and 7-9 from binding 0) and the index buffer on
  /// `vao`.
  void describeVertexFormat(GLuint vao) const;
  /// Binds the materials where the shading reads them (material_common.glsl): the colour array
  /// at texture unit 1, the data array at unit 4, the per-vertex materials and the table at
  /// storage bindings 10, 11 (the morph texture is bound with the palette: PaletteTexture).
  void bindMaterials() const;
  /// The index range of `sub_mesh` at `lod` (its last LOD when `lod` is past it).
  IndexRange lodRange(uint32_t sub_mesh, uint32_t lod) const {
    const std::vector<IndexRange>& lods = sub_meshes[sub_mesh].lods;
    return lods[std::min<size_t>(lod, lods.size() - 1)];
  }
  /// What a batch of (`sub_mesh`, `lod`) draws: lodRange(), or nothing for a sub-mesh past the
  /// character's (a crowd made for more). Empty too where the part is dropped at that LOD
  /// (buildPartLods).
  IndexRange drawnRange(uint32_t sub_mesh, uint32_t lod) const {
    return sub_mesh < sub_meshes.size() ? lodRange(sub_mesh, lod) : IndexRange{};
  }

  GLuint vao = kNoObject, vertex_buffer = kNoObject, index_buffer = kNoObject;
  GLuint base_texture = kNoObject;  ///< GL_TEXTURE_2D_ARRAY (sRGB): the colour layers.
  GLuint data_texture = kNoObject;  ///< GL_TEXTURE_2D_ARRAY (linear): the data layers.
  GLuint vertex_materials = kNoObject, material_table = kNoObject;
  /// GL_TEXTURE_2D (RGBA32UI): the mesh's si::MorphStream, when it has morph targets.
  GLuint morph_texture = kNoObject;
  std::vector<SubMesh> sub_meshes;
  uint32_t vertex_count = 0;
  uint32_t stride_bytes = 32;
  bool wide_joints = false;
  uint32_t tangent_offset = 0;  ///< VertexStream::tangent_offset (0: no tangents).
  uint32_t texcoord1_offset = 0;  ///< VertexStream::texcoord1_offset (0: none).
  uint32_t color_offset = 0;      ///< VertexStream::color_offset (0: no colours).
  uint32_t joints1_offset = 0;    ///< VertexStream::joints1_offset (0: 4 influences).
  uint32_t weights1_offset = 0;   ///< VertexStream::weights1_offset.
  uint32_t morph_offset = 0;      ///< VertexStream::morph_offset (0: no morph targets).
  /// si::morphShaderInfo() of the mesh's morph stream (0 without targets): the palette info
  /// block's second member.
  glm::uvec4 morph_info{0u};
  /// si::morphLodCuts() of the mesh (0 without targets): the block's last two members.
  std::array<float, kMorphLodCuts> morph_cuts{};
  /// The mesh features its draws' programs are variants for (ProgramSet::buildMeshVariants):
  /// kMeshVertexWords with texture coordinates 1 or colours, kMeshEightInfluences with a
  /// second set of influences, kMeshMorphTargets with morph targets.
  uint32_t meshFeatures() const {
    return (texcoord1_offset != 0 || color_offset != 0 ? kMeshVertexWords : 0u) |
           (joints1_offset != 0 ? kMeshEightInfluences : 0u) |
           (morph_offset != 0 ? kMeshMorphTargets : 0u);
  }
  /// A material draws both faces (glTF doubleSided): the character's draws cull no faces.
  bool double_sided = false;
  /// A material is alpha-masked (glTF MASK): the character's depth-only draws discard by it
  /// (ProgramTable::alpha_masked).
  bool alpha_masked = false;
  SkinnedMesh mesh;  ///< A copy, for the paths that read vertices on the CPU.
};

}  // namespace si::detail
