// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Compute pre-skinning: per batch, a compute dispatch skins the instances' vertices of their
// (sub-mesh, LOD) into a bounded ring; the draws then pull the skinned vertices by vertex id.
// The vertex shader does no skinning: on GPUs where few units run vertex shaders, the compute
// pass, which uses every unit, is the faster place to skin.

#include <vector>

#include "gl/paths/draw_path.h"

namespace si::detail {

class ComputePath final : public DrawPath {
 public:
  /// Compacts the vertices each (sub-mesh, LOD) uses and re-indexes its triangles to them.
  Status prepare(const DrawResources& r) override;
  /// Creates the ring if there is none (ensureRing).
  Status uploadFrame(const DrawResources& r, const PathFrame&) override {
    return ensureRing(*r.desc);
  }
  Status draw(const DrawResources& r, const PathFrame& frame, DrawStats* stats) override;
  void release() override;

  /// Creates the pre-skinned vertex ring (RendererDesc::compute_ring_bytes) if there is none.
  Status ensureRing(const RendererDesc& desc);
  /// Bytes of the ring (0 until first used).
  uint64_t ringBytes() const { return ring_ != kNoObject ? ring_vertices_ * 16 : 0; }
  /// Vertices of sub-mesh 0 at LOD 0 (the automatic path choice measures with it).
  uint32_t firstLodVertices() const {
    return lods_.empty() || lods_[0].empty() ? 0 : lods_[0][0].vertex_count;
  }

 private:
  struct Lod {
    uint32_t first_index = 0, index_count = 0;     // Into index_buffer_ (local indices).
    uint32_t vertex_offset = 0, vertex_count = 0;  // Into the LOD vertex list.
  };
  struct PendingDraw {
    DrawBatch batch;
    Lod lod;
    uint32_t first_instance, instances, ring_first;
  };
  const Lod& lod(uint32_t sub_mesh, uint32_t level) const {
    const std::vector<Lod>& lods = lods_[sub_mesh];
    return lods[std::min<size_t>(level, lods.size() - 1)];
  }

  std::vector<std::vector<Lod>> lods_;  // [sub_mesh][lod]
  GLuint vao_ = kNoObject, index_buffer_ = kNoObject, lod_vertex_list_ = kNoObject;
  GLuint ring_ = kNoObject;
  uint64_t ring_vertices_ = 0;
  uint32_t source_words_ = 8, max_lod_vertices_ = 0;
  std::vector<PendingDraw> pending_;
};

}  // namespace si::detail
