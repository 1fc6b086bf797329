// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The character on the GPU: the vertex stream (si/core/shader_inputs.h) and index buffer, the
// vertex array that describes them, every sub-mesh's LOD ranges, and the base colour.

#include <glad/gl.h>

#include <glm/glm.hpp>
#include <vector>

#include "gl/programs/program_set.h"
#include "si/core/baked_palette.h"
#include "si/core/character.h"

namespace si::detail {

struct CharacterBuffers {
  /// Uploads `character` for `palette` (the palette baked for it). Fails, keeping what was
  /// uploaded before, with kInvalidArgument for an invalid mesh, a palette of another skeleton
  /// or a vertex weighted to a joint the palette does not store.
  Status upload(const Character& character, const BakedPalette& palette);
  void release();
  bool ready() const { return vao != kNoObject; }

  /// Sets the vertex format (attributes 0-4 from binding 0) and the index buffer on `vao`.
  void describeVertexFormat(GLuint vao) const;
  /// The index range of `sub_mesh` at `lod` (its last LOD when `lod` is past it).
  IndexRange lodRange(uint32_t sub_mesh, uint32_t lod) const {
    const std::vector<IndexRange>& lods = sub_meshes[sub_mesh].lods;
    return lods[std::min<size_t>(lod, lods.size() - 1)];
  }

  GLuint vao = kNoObject, vertex_buffer = kNoObject, index_buffer = kNoObject;
  GLuint base_texture = kNoObject;
  glm::vec4 base_factor{1.0f};
  std::vector<SubMesh> sub_meshes;
  uint32_t vertex_count = 0;
  uint32_t stride_bytes = 32;
  bool wide_joints = false;
  SkinnedMesh mesh;  ///< A copy, for the paths that read vertices on the CPU.
};

}  // namespace si::detail
