// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The CPU-skinning baseline: per visible instance, its joint matrices and morph target weights
// from the palette, the vertices of its worn sub-meshes at its LOD morphed and skinned on the
// CPU (si::emulateSkinning's arithmetic), streamed to the GPU in camera-relative world space
// and drawn unskinned.

#include <array>
#include <vector>

#include "gl/paths/draw_path.h"
#include "gl/paths/live_palette.h"

namespace si::detail {

class CpuSkinningPath final : public DrawPath {
 public:
  /// Finds the vertex range each (sub-mesh, LOD) uses and describes the streamed format.
  Status prepare(const DrawResources& r) override;
  Status draw(const DrawResources& r, const PathFrame& frame, DrawStats* stats) override;
  void release() override;

 private:
  struct PendingDraw {
    IndexRange range;
    GLint base_vertex;
    uint32_t color;
    uint32_t lod;
    uint32_t handle;  ///< Its InstanceHandle::id (a material may read it).
  };
  GLuint vao_ = kNoObject;  // Its vertex buffer: ScratchBuffers::cpu_stream.
  std::vector<uint8_t> vertices_;
  std::vector<PendingDraw> pending_;
  std::vector<glm::uvec2> ranges_;              // Per (sub-mesh, lod): first vertex, count.
  std::vector<std::vector<uint32_t>> range_of_;  // [sub_mesh][lod] -> ranges_.
  size_t chunk_bytes_ = 0;  // The stream's size for this character: 8 MiB or its largest range.
  size_t vertex_bytes_ = 32;     // Position, normal, texcoord as floats, then the optional words.
  size_t tangent_offset_ = 0;    // 4 floats; 0 when the mesh has no tangents.
  size_t texcoord1_offset_ = 0;  // 2 floats; 0 when the mesh has no texture coordinates 1.
  size_t color_offset_ = 0;      // 4 x unorm8; 0 when the mesh has no colours.
  // The mesh's morph targets by vertex (empty without): vertex v's entries are
  // morph_entries_[morph_first_[v] .. morph_first_[v + 1]).
  struct MorphEntry {
    uint32_t target;
    float tail;  // How far it and the rest of its run can move the vertex (model units).
    glm::vec3 position, normal, tangent;
  };
  std::array<float, kMorphLodCuts> morph_cuts_{};  // Per LOD level (si::morphLodCuts).
  std::vector<uint32_t> morph_first_;
  std::vector<MorphEntry> morph_entries_;
  std::vector<float> morph_weights_;  // The drawn instance's.
  LivePalette live_palette_;          // The palette with the crowd's live poses, when it has room.
};

}  // namespace si::detail
