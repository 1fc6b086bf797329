// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Occlusion culling's depth pyramid: the bound draw framebuffer's depth over the viewport,
// blitted into a depth texture of the same format, then reduced level by level to the farthest
// depth of each 2 x 2 block (shaders/hiz.comp.glsl: the largest, or the smallest under
// reverse-Z) in an R32F mip chain.
#include "gl/programs/program_set.h"
#include "si/core/status.h"

namespace si::detail {

class DepthPyramid {
 public:
  /// Builds the pyramid from what the bound draw framebuffer's depth holds now. Recreates its
  /// textures when the viewport's size, the depth format or the sample count changes (both are
  /// queried when the bound framebuffer changes: attach another depth buffer to the same
  /// framebuffer object and the next build may fail to blit). A multisampled depth is copied
  /// with its samples and level 0 takes each pixel's farthest sample. kUnsupported for a
  /// framebuffer without a depth this can copy; createTexture2D()'s status when a texture
  /// cannot be made.
  /// `far_is_max`: window depth grows with distance (the farthest depth is the largest);
  /// false for reverse-Z (or a depth range from far to near), where the pyramid keeps minima.
  Status build(const ProgramSet& programs, bool far_is_max);
  GLuint texture() const { return pyramid_; }
  int width() const { return width_; }    ///< Of the viewport (level 0's texels from 0).
  int height() const { return height_; }
  int levels() const { return levels_; }
  /// Its textures' bytes (the depth copy and the pyramid).
  uint64_t gpuBytes() const;
  void release();

 private:
  GLuint depth_ = kNoObject, fbo_ = kNoObject, pyramid_ = kNoObject;
  GLenum depth_format_ = 0;
  GLuint framebuffer_ = 0;  // The one depth_format_ was queried for.
  int width_ = 0, height_ = 0, levels_ = 0;  // The viewport's size; the pyramid's levels.
  int pyramid_width_ = 0, pyramid_height_ = 0;  // Level 0: powers of two.
  GLint samples_ = 0;  // Of the depth copy: the framebuffer's (0: single-sampled).
};

}  // namespace si::detail
