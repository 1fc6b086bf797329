// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// GPU-driven culling and LOD: CrowdManager::update()'s selection and records computed by three
// compute passes over the crowd's state in shader storage (shaders/cull*.comp.glsl), bucketed
// per (LOD, sub-mesh) and drawn with one glMultiDrawElementsIndirect. The selection arithmetic
// is src/crowd/cull_math.h's, so both select exactly the same instances and LODs.

#include <vector>

#include "gl/paths/draw_path.h"

namespace si::detail {

class GpuCulledPath final : public DrawPath {
 public:
  Status prepare(const DrawResources&) override { return Status::ok(); }
  /// Uploads the crowd's state when it changed and sets the frame's parameters.
  /// kInvalidArgument when the crowd plays another palette or has more buckets than 256.
  Status uploadFrame(const DrawResources& r, const PathFrame& frame) override;
  Status draw(const DrawResources& r, const PathFrame& frame, DrawStats* stats) override;
  void release() override;

  /// After the timer read: visible instances and triangles from the GPU's counters.
  void readCounts(const DrawResources& r, const CrowdDesc& desc, DrawStats* stats) const;
  /// The last frame's selection: (dense index, LOD) per visible instance.
  Status readSelection(std::vector<glm::uvec2>* selection) const;

 private:
  // Uploads the crowd's state when it changed (or the crowd, its shape or the character did).
  Status uploadState(const DrawResources& r, const CrowdManager& crowd, uint32_t buckets);

  GLuint vao_ = kNoObject;
  GLuint state_ = kNoObject, clips_ = kNoObject, times_ = kNoObject, counters_ = kNoObject;
  GLuint records_ = kNoObject, visible_ = kNoObject, entries_ = kNoObject, identity_ = kNoObject;
  GLuint commands_ = kNoObject, ranges_ = kNoObject;
  uint32_t capacity_ = 0, instances_ = 0, buckets_ = 0, sub_meshes_ = 0;
  uint64_t version_ = 0;
  const CrowdManager* crowd_ = nullptr;
  GLuint vertex_source_ = kNoObject;  // The vertex buffer the VAO was made for.
};

}  // namespace si::detail
