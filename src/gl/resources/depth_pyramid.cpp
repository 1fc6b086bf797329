// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "gl/resources/depth_pyramid.h"

#include <algorithm>

#include "core/str_cat.h"
#include "gl/resources/gl_allocation.h"

namespace si::detail {
namespace {

using detail::strCat;

// The depth format of the draw framebuffer's depth attachment (0: none) and its samples (0:
// single-sampled), for a blit's target.
Status depthFormat(GLuint framebuffer, GLenum* format, GLint* samples) {
  *samples = 0;
  glGetNamedFramebufferParameteriv(framebuffer, GL_SAMPLES, samples);
  const GLenum attachment = framebuffer == 0 ? GL_DEPTH : GL_DEPTH_ATTACHMENT;
  const GLenum stencil_attachment = framebuffer == 0 ? GL_STENCIL : GL_STENCIL_ATTACHMENT;
  GLint type = GL_NONE, depth_bits = 0, stencil_bits = 0, component = GL_NONE;
  glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
  if (type != GL_NONE) {
    glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment,
                                               GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, &depth_bits);
    glGetNamedFramebufferAttachmentParameteriv(
        framebuffer, attachment, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE, &component);
    GLint stencil_type = GL_NONE;
    glGetNamedFramebufferAttachmentParameteriv(framebuffer, stencil_attachment,
                                               GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &stencil_type);
    if (stencil_type != GL_NONE)
      glGetNamedFramebufferAttachmentParameteriv(
          framebuffer, stencil_attachment, GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE, &stencil_bits);
  }
  const bool is_float = component == GL_FLOAT;
  *format = depth_bits == 16 && !is_float && stencil_bits == 0   ? GL_DEPTH_COMPONENT16
            : depth_bits == 24 && stencil_bits == 8              ? GL_DEPTH24_STENCIL8
            : depth_bits == 24 && stencil_bits == 0              ? GL_DEPTH_COMPONENT24
            : depth_bits == 32 && is_float && stencil_bits == 8  ? GL_DEPTH32F_STENCIL8
            : depth_bits == 32 && is_float && stencil_bits == 0  ? GL_DEPTH_COMPONENT32F
            : depth_bits == 32 && !is_float && stencil_bits == 0 ? GL_DEPTH_COMPONENT32
                                                                 : GLenum(0);
  if (*format == 0)
    return {StatusCode::kUnsupported,
            strCat("occlusion culling: the framebuffer's depth (", depth_bits, " bits",
                   is_float ? " float" : "", ", stencil ", stencil_bits,
                   " bits) is none this renderer can copy")};
  return Status::ok();
}

}  // namespace

Status DepthPyramid::build(const ProgramSet& programs, bool far_is_max) {
  GLint framebuffer = 0, viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  glGetIntegerv(GL_VIEWPORT, viewport);
  // Framebuffer queries can wait for the GPU on some drivers: the format is queried again only
  // when the bound framebuffer changes.
  GLenum format = depth_format_;
  GLint samples = samples_;
  Status s;
  if (GLuint(framebuffer) != framebuffer_ || depth_format_ == 0) {
    s = depthFormat(GLuint(framebuffer), &format, &samples);
    if (!s.isOk()) return s;
    framebuffer_ = GLuint(framebuffer);
  }
  const int w = std::max(1, viewport[2]), h = std::max(1, viewport[3]);
  if (w != width_ || h != height_ || format != depth_format_ || samples != samples_ ||
      pyramid_ == kNoObject) {
    width_ = height_ = levels_ = 0;  // Until both textures exist.
    // Level 0 has power-of-two sides at least the viewport's, so every level halves exactly.
    int pw = 1, ph = 1, levels = 1;
    while (pw < w) pw *= 2;
    while (ph < h) ph *= 2;
    while ((std::max(pw, ph) >> (levels - 1)) > 1) ++levels;
    // A multisampled depth is copied as it is (a blit between equal sample counts); the copy
    // pass takes each pixel's farthest sample, never one sample's depth.
    s = samples > 0 ? createTexture2DMultisample(&depth_, samples, format, w, h,
                                                 "occlusion culling: the depth copy")
                    : createTexture2D(&depth_, 1, format, w, h, "occlusion culling: the depth copy");
    if (s.isOk())
      s = createTexture2D(&pyramid_, levels, GL_R32F, pw, ph,
                          "occlusion culling: the depth pyramid");
    if (!s.isOk()) return s;
    if (fbo_ == kNoObject) glCreateFramebuffers(1, &fbo_);
    glNamedFramebufferTexture(fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
    glTextureParameteri(pyramid_, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTextureParameteri(pyramid_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    if (samples == 0) {  // Multisampled textures have no sampling state.
      glTextureParameteri(depth_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTextureParameteri(depth_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glTextureParameteri(depth_, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    }
    width_ = w, height_ = h, levels_ = levels, depth_format_ = format, samples_ = samples;
    pyramid_width_ = pw, pyramid_height_ = ph;
  }
  glBlitNamedFramebuffer(GLuint(framebuffer), fbo_, viewport[0], viewport[1], viewport[0] + w,
                         viewport[1] + h, 0, 0, w, h, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
  // Level 0 from the copy, then each level from the one below.
  const GLuint copy =
      programs[samples_ > 0 ? ProgramId::kHizCopyMultisample : ProgramId::kHizCopy].id;
  glUseProgram(copy);
  if (samples_ > 0) glProgramUniform1i(copy, 3, samples_);
  glBindTextureUnit(0, depth_);
  glBindImageTexture(0, pyramid_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glProgramUniform2i(copy, 0, pyramid_width_, pyramid_height_);
  glProgramUniform2i(copy, 1, w, h);
  glProgramUniform1i(copy, 2, far_is_max ? 1 : 0);
  glDispatchCompute(GLuint(pyramid_width_ + 7) / 8, GLuint(pyramid_height_ + 7) / 8, 1);
  const GLuint reduce = programs[ProgramId::kHizReduce].id;
  glUseProgram(reduce);
  glProgramUniform1i(reduce, 2, far_is_max ? 1 : 0);
  int lw = pyramid_width_, lh = pyramid_height_;
  for (int level = 1; level < levels_; ++level) {
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    const int nw = std::max(1, lw / 2), nh = std::max(1, lh / 2);
    glBindImageTexture(0, pyramid_, level - 1, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    glBindImageTexture(1, pyramid_, level, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glProgramUniform2i(reduce, 0, nw, nh);
    glProgramUniform2i(reduce, 1, lw, lh);
    glDispatchCompute(GLuint(nw + 7) / 8, GLuint(nh + 7) / 8, 1);
    lw = nw, lh = nh;
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  return Status::ok();
}

void DepthPyramid::release() {
  const GLuint textures[] = {depth_, pyramid_};
  glDeleteTextures(2, textures);
  if (fbo_ != kNoObject) glDeleteFramebuffers(1, &fbo_);
  *this = DepthPyramid();
}

uint64_t DepthPyramid::gpuBytes() const {
  return textureBytes(depth_) + textureBytes(pyramid_);
}

}  // namespace si::detail
