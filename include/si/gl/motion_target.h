// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// An offscreen framebuffer holding what the renderer's motion vectors (RendererDesc::
/// motion_vectors) write: colour at fragment output 0 (RGBA8), screen motion at output 1
/// (RG16F, texture coordinate units) and depth (32-bit float). For the examples, tests and
/// engines without a G-buffer of their own; an engine with one binds its own attachments.
///
/// Usage (context current, after loadGl):
/// \code
///   si::MotionTarget target;
///   si::Status s = target.create(1920, 1080);
///   target.clear(glm::vec4(0.6f, 0.65f, 0.6f, 1.0f));  // binds it

///   s = renderer.drawCrowd(crowd, batcher, camera, &stats);
///   si::MotionSummary summary;
///   s = target.summarize(&summary);       // mean and largest motion in pixels
///   target.restore();                     // the framebuffer bound before
///   target.blitColor(0, 1920, 1080);      // show it (into a single-sampled framebuffer)
/// \endcode

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/status.h"

namespace si {

/// What a motion image holds, over the pixels something was drawn to (depth below the far
/// plane's 1): their count and the mean and largest motion length in pixels.
struct MotionSummary {
  uint64_t drawn_pixels = 0;
  double mean_pixels = 0.0;
  double max_pixels = 0.0;
};

class MotionTarget {
 public:
  MotionTarget() = default;
  ~MotionTarget();  ///< Releases its GL objects (the context must be current).
  MotionTarget(const MotionTarget&) = delete;
  MotionTarget& operator=(const MotionTarget&) = delete;

  /// (Re)creates the framebuffer of `width` x `height` pixels. kInvalidArgument for a zero
  /// side or one past GL_MAX_RENDERBUFFER_SIZE; kBackend when it is not complete or a GL error
  /// occurred (named); nothing kept then.
  Status create(uint32_t width, uint32_t height);
  /// Binds it as the draw and read framebuffer (both draw buffers) and sets the viewport,
  /// remembering the framebuffers and viewport bound before (restore()). Called while it is
  /// bound (clear() every frame), it keeps what was bound before it.
  void bind();
  /// Clears colour to `color`, motion to 0 and depth to 1 (binds it).
  void clear(const glm::vec4& color);
  /// Binds again the framebuffers and viewport that were bound before bind() (or clear())
  /// bound this target.
  void restore() const;
  /// The motion image, width * height texels from the bottom row up, in texture coordinate
  /// units (multiply by the size for pixels). kInvalidArgument before create() or for a null out.
  Status readMotion(std::vector<glm::vec2>* out) const;
  /// The colour image, RGBA8, as readMotion orders it.
  Status readColor(std::vector<uint8_t>* rgba) const;
  /// The depth image (window depth in [0, 1]), as readMotion orders it.
  Status readDepth(std::vector<float>* out) const;
  /// Reads motion and depth and summarizes the drawn pixels' motion.
  Status summarize(MotionSummary* out) const;
  /// Copies the colour into framebuffer `framebuffer` (0: the default one) of `width` x
  /// `height`, scaled linearly.
  void blitColor(uint32_t framebuffer, uint32_t width, uint32_t height) const;
  /// Deletes its GL objects (context current). Idempotent.
  void release();

  uint32_t framebuffer() const { return framebuffer_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

 private:
  uint32_t framebuffer_ = 0, color_ = 0, motion_ = 0, depth_ = 0;
  uint32_t width_ = 0, height_ = 0;
  int32_t saved_draw_ = 0, saved_read_ = 0, saved_viewport_[4] = {0, 0, 0, 0};
};

}  // namespace si
