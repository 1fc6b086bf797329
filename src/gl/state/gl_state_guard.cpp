// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Saving and restoring the host's GL state around the library's calls (the pattern of Dear
// ImGui's imgui_impl_opengl3.cpp, ImGui_ImplOpenGL3_RenderDrawData).
#include "gl/state/gl_state_guard.h"

#include <initializer_list>

#include "gl/profile/gl_profile.h"

namespace si::detail {

namespace {

constexpr uint32_t bits(std::initializer_list<int> indices) {
  uint32_t m = 0;
  for (int i : indices) m |= 1u << i;
  return m;
}

// Which bindings the library's programs use (src/gl/shaders; docs/glsl-interface.md lists the
// shipped include's defaults):
//   uniform buffers 0-3: records, previous records, layer records, previous layer records; 4:
//     the palette's info block;
//   storage 1-4, 8-11: compute pre-skinning (ring, source, list, previous ring), the mask
//     table, the impostor clip table, the material buffers; 23-27: the compose table, the
//     record ring, drawCrowd's previous records, the composed rows (current and previous);
//     28: the pre-skinned tangent ring (compute and GPU-driven pre-skinning); 29: the slots'
//     instance handles; 30: the slots' composed records (drawCrowd); the GPU-driven passes use
//     0-23, 25-28 (25: the live pose slots);
//   texture units 0-4: palette (or the depth copy), colour array (or the depth pyramid),
//     custom array, impostor atlas, material data array; 5: the morph targets' entries; image
//     units 0-1: the depth pyramid's levels.
constexpr uint32_t kUniforms = bits({0, 1, 2, 3, 4});
constexpr uint32_t kDrawStorage = bits({1, 2, 3, 4, 8, 9, 10, 11, 23, 24, 25, 26, 27, 28, 29, 30});
constexpr uint32_t kAllStorage = kDrawStorage | ((1u << 24) - 1u);
constexpr uint32_t kUnits = bits({0, 1, 2, 3, 4, 5});

constexpr GLenum kUnpack[8] = {GL_UNPACK_SWAP_BYTES,  GL_UNPACK_LSB_FIRST,  GL_UNPACK_ROW_LENGTH,
                               GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_ROWS,  GL_UNPACK_SKIP_PIXELS,
                               GL_UNPACK_SKIP_IMAGES,  GL_UNPACK_ALIGNMENT};
constexpr GLenum kPack[8] = {GL_PACK_SWAP_BYTES,  GL_PACK_LSB_FIRST,  GL_PACK_ROW_LENGTH,
                             GL_PACK_IMAGE_HEIGHT, GL_PACK_SKIP_ROWS,  GL_PACK_SKIP_PIXELS,
                             GL_PACK_SKIP_IMAGES,  GL_PACK_ALIGNMENT};

// Which of kUnpack / kPack ES 3.0 has (no byte swapping or bit order; packing has no images).
constexpr bool kEsUnpack[8] = {false, false, true, true, true, true, true, true};
constexpr bool kEsPack[8] = {false, false, true, false, true, true, false, true};
bool hasPixelStore(bool pack, int k) {
  return !esProfile() || (pack ? kEsPack[k] : kEsUnpack[k]);
}

void setEnabled(GLenum cap, GLboolean on) {
  if (on) glEnable(cap);
  else glDisable(cap);
}

// The enables an offscreen pass turns off (GlFootprint::raster): whatever the host left on
// among them would change what the pass draws or clears (rasterizer discard drops clears too).
constexpr GLenum kOffscreenCaps[] = {
    GL_RASTERIZER_DISCARD, GL_BLEND, GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_POLYGON_OFFSET_FILL, GL_POLYGON_OFFSET_LINE,
    GL_POLYGON_OFFSET_POINT, GL_SAMPLE_ALPHA_TO_COVERAGE, GL_SAMPLE_ALPHA_TO_ONE,
    GL_SAMPLE_COVERAGE, GL_SAMPLE_MASK, GL_SAMPLE_SHADING, GL_COLOR_LOGIC_OP, GL_DEPTH_CLAMP,
    GL_FRAMEBUFFER_SRGB, GL_CLIP_DISTANCE0, GL_CLIP_DISTANCE1, GL_CLIP_DISTANCE2,
    GL_CLIP_DISTANCE3, GL_CLIP_DISTANCE4, GL_CLIP_DISTANCE5};

}  // namespace

GlFootprint drawFootprint() {
  GlFootprint f;
  f.uniform_buffers = kUniforms;
  f.storage_buffers = kDrawStorage;
  f.texture_units = kUnits;
  f.draw = true;
  return f;
}

GlFootprint gpuDrivenFootprint() {
  GlFootprint f = drawFootprint();
  f.storage_buffers = kAllStorage;
  f.image_units = bits({0, 1});
  return f;
}

GlFootprint uploadFootprint() {
  GlFootprint f = drawFootprint();  // The automatic path choice draws both skinning paths
  f.framebuffer = true;             // (and buildImpostor its atlas) into a framebuffer of its
  f.raster = true;                  // own, under the raster state of its own.
  f.unpack = true;
  return f;
}

GlFootprint captureFootprint() {
  GlFootprint f = drawFootprint();
  f.transform_feedback = true;
  return f;
}

GlFootprint readbackFootprint() {
  GlFootprint f;
  f.pack = true;
  return f;
}

void GlStateGuard::saveIndexed(GLenum binding, GLenum start, GLenum size, uint32_t mask,
                               IndexedBuffer* out) {
  for (int i = 0; i < kMaxIndexed; ++i) {
    if (!(mask >> i & 1u)) continue;
    glGetIntegeri_v(binding, GLuint(i), &out[i].buffer);
    // No buffer is restored as none (glBindBufferBase of 0) whatever its range reads, so the
    // range is asked for only with a buffer: in a browser the binding is answered by the page,
    // the range by a round trip to the GPU process (docs/web.md).
    if (out[i].buffer == 0) continue;
    glGetInteger64i_v(start, GLuint(i), &out[i].start);
    glGetInteger64i_v(size, GLuint(i), &out[i].size);
  }
}

void GlStateGuard::restoreIndexed(GLenum target, uint32_t mask, const IndexedBuffer* saved) const {
  for (int i = 0; i < kMaxIndexed; ++i) {
    if (!(mask >> i & 1u)) continue;
    const IndexedBuffer& b = saved[i];
    // A whole-buffer binding (glBindBufferBase, or none) reports size 0.
    if (b.buffer == 0 || b.size == 0) glBindBufferBase(target, GLuint(i), GLuint(b.buffer));
    else glBindBufferRange(target, GLuint(i), GLuint(b.buffer), GLintptr(b.start),
                           GLsizeiptr(b.size));
  }
}

void GlStateGuard::saveRaster() {
  static_assert(sizeof(kOffscreenCaps) / sizeof(kOffscreenCaps[0]) == kRasterCaps,
                "one saved value per offscreen enable");
  for (int k = 0; k < kRasterCaps; ++k) raster_caps_[k] = glIsEnabled(kOffscreenCaps[k]);
  glGetIntegerv(GL_DEPTH_FUNC, &depth_func_);
  glGetDoublev(GL_DEPTH_RANGE, depth_range_);
  glGetIntegerv(GL_CLIP_ORIGIN, &clip_origin_);
  glGetIntegerv(GL_CLIP_DEPTH_MODE, &clip_depth_);
  glGetIntegerv(GL_POLYGON_MODE, polygon_mode_);  // Front and back (one mode in core).
}

void GlStateGuard::setRaster() const {
  for (GLenum cap : kOffscreenCaps) glDisable(cap);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDepthRange(0.0, 1.0);
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void GlStateGuard::restoreRaster() const {
  for (int k = 0; k < kRasterCaps; ++k) setEnabled(kOffscreenCaps[k], raster_caps_[k]);
  glDepthFunc(GLenum(depth_func_));
  glDepthRange(depth_range_[0], depth_range_[1]);
  glClipControl(GLenum(clip_origin_), GLenum(clip_depth_));
  glPolygonMode(GL_FRONT_AND_BACK, GLenum(polygon_mode_[0]));
}

void GlStateGuard::savePixelStore(bool pack, PixelStore* out) {
  const GLenum* names = pack ? kPack : kUnpack;
  for (int k = 0; k < 8; ++k)
    if (hasPixelStore(pack, k)) glGetIntegerv(names[k], &out->values[k]);
  glGetIntegerv(pack ? GL_PIXEL_PACK_BUFFER_BINDING : GL_PIXEL_UNPACK_BUFFER_BINDING, &out->buffer);
}

void GlStateGuard::restorePixelStore(bool pack, const PixelStore& saved) {
  const GLenum* names = pack ? kPack : kUnpack;
  for (int k = 0; k < 8; ++k)
    if (hasPixelStore(pack, k)) glPixelStorei(names[k], saved.values[k]);
  glBindBuffer(pack ? GL_PIXEL_PACK_BUFFER : GL_PIXEL_UNPACK_BUFFER, GLuint(saved.buffer));
}

// Tightly packed rows from client memory: what every upload and readback of the library means.
void GlStateGuard::setDefaultPixelStore(bool pack) {
  const GLenum* names = pack ? kPack : kUnpack;
  for (int k = 0; k < 7; ++k)
    if (hasPixelStore(pack, k)) glPixelStorei(names[k], 0);
  glPixelStorei(names[7], 1);
  glBindBuffer(pack ? GL_PIXEL_PACK_BUFFER : GL_PIXEL_UNPACK_BUFFER, 0);
}

GlStateGuard::GlStateGuard(const GlFootprint& footprint, bool restore, bool webgl_raster)
    : footprint_(footprint),
      restore_(restore),
      es_(esProfile()),
      webgl_(webglProfile()),
      raster_(!webgl_ || webgl_raster) {
  if (es_) {  // No storage buffers, image units, indirect or query buffers, transform capture,
              // offscreen passes.
    footprint_.raster = false;
    // The material table a draw reads from storage binding 11 is a uniform block there.
    if (footprint_.storage_buffers >> 11 & 1u) footprint_.uniform_buffers |= 1u << 11;
    footprint_.storage_buffers = 0;
    footprint_.image_units = 0;
    footprint_.transform_feedback = false;
  }
  const GlFootprint& f = footprint_;
  if (restore_) {
    saveIndexed(GL_UNIFORM_BUFFER_BINDING, GL_UNIFORM_BUFFER_START, GL_UNIFORM_BUFFER_SIZE,
                f.uniform_buffers, uniform_);
    saveIndexed(GL_SHADER_STORAGE_BUFFER_BINDING, GL_SHADER_STORAGE_BUFFER_START,
                GL_SHADER_STORAGE_BUFFER_SIZE, f.storage_buffers, storage_);
    if (f.uniform_buffers) glGetIntegerv(GL_UNIFORM_BUFFER_BINDING, &generic_uniform_);
    if (f.storage_buffers) glGetIntegerv(GL_SHADER_STORAGE_BUFFER_BINDING, &generic_storage_);
    if (f.texture_units) {
      glGetIntegerv(GL_ACTIVE_TEXTURE, &active_texture_);
      for (int u = 0; u < kMaxUnits; ++u) {
        if (!(f.texture_units >> u & 1u)) continue;
        glActiveTexture(GLenum(GL_TEXTURE0 + u));
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &units_[u].texture_2d);
        glGetIntegerv(GL_TEXTURE_BINDING_2D_ARRAY, &units_[u].texture_2d_array);
        if (!es_)  // Occlusion culling's copy of a multisampled depth.
          glGetIntegerv(GL_TEXTURE_BINDING_2D_MULTISAMPLE, &units_[u].texture_2d_multisample);
        glGetIntegerv(GL_SAMPLER_BINDING, &units_[u].sampler);
      }
      glActiveTexture(GLenum(active_texture_));
    }
    for (int i = 0; i < kMaxUnits; ++i) {
      if (!(f.image_units >> i & 1u)) continue;
      Image& m = images_[i];
      glGetIntegeri_v(GL_IMAGE_BINDING_NAME, GLuint(i), &m.texture);
      glGetIntegeri_v(GL_IMAGE_BINDING_LEVEL, GLuint(i), &m.level);
      glGetIntegeri_v(GL_IMAGE_BINDING_LAYER, GLuint(i), &m.layer);
      glGetIntegeri_v(GL_IMAGE_BINDING_ACCESS, GLuint(i), &m.access);
      glGetIntegeri_v(GL_IMAGE_BINDING_FORMAT, GLuint(i), &m.format);
      glGetBooleani_v(GL_IMAGE_BINDING_LAYERED, GLuint(i), &m.layered);
    }
    if (f.draw) {
      glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
      glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertex_array_);
      if (!es_) {
        glGetIntegerv(GL_DRAW_INDIRECT_BUFFER_BINDING, &draw_indirect_);
        glGetIntegerv(GL_DISPATCH_INDIRECT_BUFFER_BINDING, &dispatch_indirect_);
        glGetIntegerv(GL_QUERY_BUFFER_BINDING, &query_buffer_);
        primitive_restart_ = glIsEnabled(GL_PRIMITIVE_RESTART);
      }
      depth_test_ = glIsEnabled(GL_DEPTH_TEST);
      cull_face_ = glIsEnabled(GL_CULL_FACE);
      blend_ = glIsEnabled(GL_BLEND);
      rasterizer_discard_ = glIsEnabled(GL_RASTERIZER_DISCARD);
      if (!webgl_) fixed_index_restart_ = glIsEnabled(GL_PRIMITIVE_RESTART_FIXED_INDEX);
      if (raster_) {  // Else restored as GL's defaults (the members' initial values).
        glGetIntegerv(GL_CULL_FACE_MODE, &cull_face_mode_);
        glGetIntegerv(GL_FRONT_FACE, &front_face_);
        glGetBooleanv(GL_COLOR_WRITEMASK, color_mask_);
        glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
      }
    }
    if (f.raster) {
      if (!f.draw && raster_) glGetBooleanv(GL_COLOR_WRITEMASK, color_mask_);
      if (!f.draw && raster_) glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
      saveRaster();
    }
    if (f.framebuffer) {
      glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_framebuffer_);
      glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_framebuffer_);
      glGetIntegerv(GL_VIEWPORT, viewport_);
    }
    if (f.unpack) savePixelStore(false, &unpack_);
    if (f.pack) savePixelStore(true, &pack_);
    if (f.transform_feedback) {
      saveIndexed(GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, GL_TRANSFORM_FEEDBACK_BUFFER_START,
                  GL_TRANSFORM_FEEDBACK_BUFFER_SIZE, 1u, &feedback_);
      glGetIntegerv(GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, &generic_feedback_);
    }
  }
  // What the library's draws need, whatever the host left.
  if (f.draw) {
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glDisable(GL_RASTERIZER_DISCARD);
    glDepthMask(GL_TRUE);  // Opaque: the crowd writes its depth and blends nothing.
    glDisable(GL_BLEND);
    if (!webgl_) glDisable(GL_PRIMITIVE_RESTART_FIXED_INDEX);  // Always on in WebGL 2.
    if (!es_) {
      glDisable(GL_PRIMITIVE_RESTART);
      glBindBuffer(GL_QUERY_BUFFER, 0);
    }
  }
  if (f.raster) setRaster();
  if (f.texture_units) {  // Each texture's own sampling parameters, not a sampler object's.
    for (int u = 0; u < kMaxUnits; ++u)
      if (f.texture_units >> u & 1u) glBindSampler(GLuint(u), 0);
  }
  if (f.unpack) setDefaultPixelStore(false);
  if (f.pack) setDefaultPixelStore(true);
}

GlStateGuard::~GlStateGuard() {
  if (!restore_) return;
  const GlFootprint& f = footprint_;
  // Indexed bindings first: binding one also sets the generic binding point.
  restoreIndexed(GL_UNIFORM_BUFFER, f.uniform_buffers, uniform_);
  restoreIndexed(GL_SHADER_STORAGE_BUFFER, f.storage_buffers, storage_);
  if (f.uniform_buffers) glBindBuffer(GL_UNIFORM_BUFFER, GLuint(generic_uniform_));
  if (f.storage_buffers) glBindBuffer(GL_SHADER_STORAGE_BUFFER, GLuint(generic_storage_));
  if (f.texture_units) {
    for (int u = 0; u < kMaxUnits; ++u) {
      if (!(f.texture_units >> u & 1u)) continue;
      glActiveTexture(GLenum(GL_TEXTURE0 + u));
      glBindTexture(GL_TEXTURE_2D, GLuint(units_[u].texture_2d));
      glBindTexture(GL_TEXTURE_2D_ARRAY, GLuint(units_[u].texture_2d_array));
      if (!es_) glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, GLuint(units_[u].texture_2d_multisample));
      glBindSampler(GLuint(u), GLuint(units_[u].sampler));
    }
    glActiveTexture(GLenum(active_texture_));
  }
  for (int i = 0; i < kMaxUnits; ++i) {
    if (!(f.image_units >> i & 1u)) continue;
    const Image& m = images_[i];
    glBindImageTexture(GLuint(i), GLuint(m.texture), m.level, m.layered, m.layer,
                       GLenum(m.access), GLenum(m.format));
  }
  if (f.draw) {
    // A program the host deleted while it was current lives only while current: once the
    // library's programs replaced it, it is gone, and no program is current again.
    glUseProgram(program_ != 0 && glIsProgram(GLuint(program_)) ? GLuint(program_) : 0u);
    glBindVertexArray(GLuint(vertex_array_));
    if (!es_) {
      glBindBuffer(GL_DRAW_INDIRECT_BUFFER, GLuint(draw_indirect_));
      glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, GLuint(dispatch_indirect_));
      glBindBuffer(GL_QUERY_BUFFER, GLuint(query_buffer_));
      setEnabled(GL_PRIMITIVE_RESTART, primitive_restart_);
    }
    setEnabled(GL_DEPTH_TEST, depth_test_);
    setEnabled(GL_CULL_FACE, cull_face_);
    setEnabled(GL_RASTERIZER_DISCARD, rasterizer_discard_);
    if (!webgl_) setEnabled(GL_PRIMITIVE_RESTART_FIXED_INDEX, fixed_index_restart_);
    setEnabled(GL_BLEND, blend_);
    glCullFace(GLenum(cull_face_mode_));
    glFrontFace(GLenum(front_face_));
  }
  if (f.raster) restoreRaster();
  if (f.draw || f.raster) {
    glColorMask(color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
    glDepthMask(depth_mask_);
  }
  if (f.framebuffer) {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_framebuffer_));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_framebuffer_));
    glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
  }
  if (f.unpack) restorePixelStore(false, unpack_);
  if (f.pack) restorePixelStore(true, pack_);
  if (f.transform_feedback) {
    restoreIndexed(GL_TRANSFORM_FEEDBACK_BUFFER, 1u, &feedback_);
    glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, GLuint(generic_feedback_));
  }
}

}  // namespace si::detail
