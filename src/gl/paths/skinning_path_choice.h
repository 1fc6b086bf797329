// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// SkinningPath::kAutomatic: both skinning paths timed on a synthetic crowd, the faster kept.

#include <string>

#include "gl/paths/compute_path.h"
#include "gl/paths/vertex_shader_path.h"

namespace si::detail {

struct PathChoice {
  SkinningPath path = SkinningPath::kVertexShader;
  std::string reason;
};

/// Times `vertex_path` and `compute_path` drawing a grid of about 2^20 vertices of sub-mesh 0 at
/// LOD 0 (a crowd-sized draw: smaller ones mislead on llvmpipe, whose vertex path slows
/// superlinearly; clip 0 between two frames; the best of two after a warm-up) into a 256x256
/// framebuffer of its own, and keeps the faster. The application's framebuffer and viewport
/// are restored. Uses (and fences) one region of the record ring.
Status chooseSkinningPath(const DrawResources& r, VertexShaderPath& vertex_path,
                          ComputePath& compute_path, const glm::vec3& light, PathChoice* out);

}  // namespace si::detail
