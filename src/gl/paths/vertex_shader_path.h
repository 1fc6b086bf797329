// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The technique's path: one glDrawElementsInstanced per batch, the vertex shader skinning each
// vertex with its instance's record (gl_InstanceID into the uniform block). Also draws the
// depth-only and rigid programs, which read the same records.

#include "gl/paths/draw_path.h"

namespace si::detail {

class VertexShaderPath final : public DrawPath {
 public:
  Status prepare(const DrawResources&) override { return Status::ok(); }
  Status draw(const DrawResources& r, const PathFrame& frame, DrawStats* stats) override;
  void release() override {}
};

}  // namespace si::detail
