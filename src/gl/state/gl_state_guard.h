// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The GL state contract (docs/rendering.md, "A guest in the host's engine"): every public call
// that changes context state saves what it may change on entry and puts it back on exit, as
// Dear ImGui's OpenGL 3 back-end does around its draws. A footprint says which state a call may
// change; GlStateGuard saves that state, sets the fixed-function state the library's draws need
// (depth test, back-face culling of counter-clockwise fronts, no rasterizer discard, no primitive
// restart, no query buffer, no sampler objects, default pixel store), and restores all of it
// when it goes out of scope. With RendererDesc::restore_state
// off it only sets what the draws need: the host then finds what docs/rendering.md lists.

#include <glad/gl.h>

#include <cstdint>

namespace si::detail {

/// The state a public call may change: indexed bindings by bit, the rest by flag.
struct GlFootprint {
  uint32_t uniform_buffers = 0;  ///< Bit i: uniform buffer binding i (and the generic one).
  uint32_t storage_buffers = 0;  ///< Bit i: shader storage binding i (and the generic one).
  uint32_t texture_units = 0;    ///< Bit u: unit u's 2D, 2D array and (desktop) 2D multisample
                                 ///< textures and its sampler.
  uint32_t image_units = 0;      ///< Bit i: image unit i.
  /// Program, vertex array, the draw and dispatch indirect buffers, the query buffer (its
  /// binding turns the GPU timer's result pointer into an offset), depth test, face culling
  /// (mode and front face), colour mask, rasterizer discard, primitive restart (both kinds).
  bool draw = false;
  bool framebuffer = false;         ///< Draw and read framebuffers, viewport.
  /// The offscreen passes' whole raster state (buildImpostor's capture, the automatic path
  /// measurement, measureImageLodErrors): depth function, writes and range, clip control,
  /// polygon mode, colour mask, and the blending, scissor, stencil, polygon offset, multisample
  /// coverage, logic op, depth clamp, sRGB and clip distance enables, set to GL's defaults
  /// (those enables off), so what the host left never enters an atlas or a measurement. Desktop
  /// GL only: the ES profile draws nothing offscreen.
  bool raster = false;
  bool unpack = false;              ///< Pixel unpack state and the pixel unpack buffer.
  bool pack = false;                ///< Pixel pack state and the pixel pack buffer.
  bool transform_feedback = false;  ///< Transform feedback buffer binding 0 (and the generic).
};

/// What each kind of public call may change (gl_state_guard.cpp lists the bindings).
GlFootprint drawFootprint();        ///< drawCrowd (both skinning paths), the baselines.
GlFootprint gpuDrivenFootprint();   ///< drawCrowdGpuCulled (occlusion culling included).
GlFootprint uploadFootprint();      ///< Palette and character uploads, path measurement.
GlFootprint captureFootprint();     ///< captureSkinnedPositions.
GlFootprint readbackFootprint();    ///< Reading textures back (MotionTarget).

/// Saves the state of `footprint` (when `restore`), then sets the draw state the library needs
/// (when footprint.draw: also depth writes on and blending off), the offscreen raster state
/// (when footprint.raster) and the default pixel store (when unpack or pack); the destructor
/// restores what it saved. Needs a current context with GL loaded. Not copyable.
class GlStateGuard {
 public:
  /// `webgl_raster`: under WebGL, also save the cull face mode, front face and colour mask
  /// (each a round trip to the GPU process; RendererDesc::webgl_restore_raster_state).
  GlStateGuard(const GlFootprint& footprint, bool restore, bool webgl_raster = true);
  ~GlStateGuard();
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;

 private:
  struct IndexedBuffer {
    GLint buffer = 0;
    GLint64 start = 0, size = 0;
  };
  struct Unit {
    GLint texture_2d = 0, texture_2d_array = 0, texture_2d_multisample = 0, sampler = 0;
  };
  struct Image {
    GLint texture = 0, level = 0, layer = 0, access = GL_READ_ONLY, format = GL_R8;
    GLboolean layered = GL_FALSE;
  };
  struct PixelStore {
    GLint values[8] = {};
    GLint buffer = 0;
  };
  static constexpr int kMaxIndexed = 32;
  static constexpr int kMaxUnits = 8;

  void saveIndexed(GLenum binding, GLenum start, GLenum size, uint32_t mask, IndexedBuffer* out);
  void restoreIndexed(GLenum target, uint32_t mask, const IndexedBuffer* saved) const;
  void saveRaster();
  void setRaster() const;
  void restoreRaster() const;
  void savePixelStore(bool pack, PixelStore* out);
  static void restorePixelStore(bool pack, const PixelStore& saved);
  static void setDefaultPixelStore(bool pack);

  GlFootprint footprint_;
  bool restore_ = false;
  bool es_ = false;  // The ES profile: only the state ES 3.0 has (gl_profile.h).
  bool webgl_ = false;  // WebGL 2: primitive restart at the fixed index is always on.
  bool raster_ = true;  // Save the cull face mode, front face and colour mask (see above).
  IndexedBuffer uniform_[kMaxIndexed], storage_[kMaxIndexed];
  GLint generic_uniform_ = 0, generic_storage_ = 0;
  Unit units_[kMaxUnits];
  GLint active_texture_ = GL_TEXTURE0;
  Image images_[kMaxUnits];
  GLint program_ = 0, vertex_array_ = 0, draw_indirect_ = 0, dispatch_indirect_ = 0;
  GLint query_buffer_ = 0;
  GLboolean depth_test_ = GL_FALSE, cull_face_ = GL_FALSE, rasterizer_discard_ = GL_FALSE;
  GLboolean primitive_restart_ = GL_FALSE, fixed_index_restart_ = GL_FALSE;
  GLint cull_face_mode_ = GL_BACK, front_face_ = GL_CCW;
  GLboolean color_mask_[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
  GLboolean depth_mask_ = GL_TRUE, blend_ = GL_FALSE;
  // The offscreen raster state (GlFootprint::raster): kRasterCaps' enables and the rest.
  static constexpr int kRasterCaps = 21;
  GLboolean raster_caps_[kRasterCaps] = {};
  GLint depth_func_ = GL_LESS, clip_origin_ = GL_LOWER_LEFT,
        clip_depth_ = GL_NEGATIVE_ONE_TO_ONE, polygon_mode_[2] = {GL_FILL, GL_FILL};
  GLdouble depth_range_[2] = {0.0, 1.0};
  GLint draw_framebuffer_ = 0, read_framebuffer_ = 0, viewport_[4] = {0, 0, 0, 0};
  PixelStore unpack_, pack_;
  IndexedBuffer feedback_;
  GLint generic_feedback_ = 0;
};

}  // namespace si::detail
