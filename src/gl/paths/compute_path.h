// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Compute pre-skinning: per batch, a compute dispatch skins the instances' vertices of their
// (sub-mesh, LOD) into a bounded ring; the draws then pull the skinned vertices by vertex id.
// The vertex shader does no skinning: on GPUs where few units run vertex shaders, the compute
// pass, which uses every unit, is the faster place to skin.

#include <vector>

#include "gl/paths/draw_path.h"

namespace si::detail {

/// Binds what the compute skinning passes (ProgramId::kComputeSkin and its variants) read and
/// write: the palette (texture unit 0, info block at uniform binding 4), `out` (pre-skinned
/// vertices) at storage binding 1, the character's source vertices at 2, `vertex_list` at 3 and
/// `tangents` (the tangent ring; `out` when the pass writes none, never read then) at 28.
/// The draws and Renderer::captureSkinnedPositions share it.
void bindPreSkinning(const DrawResources& r, GLuint out, GLuint vertex_list,
                     GLuint tangents = kNoObject);

class ComputePath final : public DrawPath {
 public:
  /// The vertex array of the character's re-indexed triangles (PreSkinLists).
  Status prepare(const DrawResources& r) override;
  /// Creates the ring if there is none (ensureRing).
  Status uploadFrame(const DrawResources& r, const PathFrame&) override {
    return ensureRing(r);
  }
  Status draw(const DrawResources& r, const PathFrame& frame, DrawStats* stats) override;
  void release() override;

  /// Creates the shared pre-skinned vertex ring (ScratchBuffers::compute_ring: RendererDesc::
  /// compute_ring_bytes, at least one instance of the character's largest LOD) if there is none
  /// or it is too small for the character; for a character with tangents, its tangent ring too
  /// (compute_tangent_ring, as many vertices).
  Status ensureRing(const DrawResources& r);

 private:
  struct PendingDraw {
    DrawBatch batch;
    PreSkinLists::Lod lod;
    uint32_t first_instance, instances, ring_first;
  };

  GLuint vao_ = kNoObject;
  std::vector<PendingDraw> pending_;
};

}  // namespace si::detail
