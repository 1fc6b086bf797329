// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The offscreen colour + motion + depth framebuffer of motion vectors.
#include "si/gl/motion_target.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>

#include "core/str_cat.h"
#include "gl/host_errors.h"
#include "gl/state/gl_state_guard.h"
#include "si/gl/gl_context.h"

namespace si {

MotionTarget::~MotionTarget() { release(); }

Status MotionTarget::create(uint32_t width, uint32_t height) {
  release();
  GLint limit = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &limit);
  if (width == 0 || height == 0 || width > uint32_t(limit) || height > uint32_t(limit))
    return {StatusCode::kInvalidArgument,
            detail::strCat("MotionTarget: ", width, " x ", height, " pixels (each side 1 to ",
                           limit, ", GL_MAX_RENDERBUFFER_SIZE)")};
  detail::takeHostErrors("MotionTarget::create");  // Not ours to report, nor to drop.
  const GLsizei w = GLsizei(width), h = GLsizei(height);
  glCreateTextures(GL_TEXTURE_2D, 1, &color_);
  glTextureStorage2D(color_, 1, GL_RGBA8, w, h);
  glCreateTextures(GL_TEXTURE_2D, 1, &motion_);
  glTextureStorage2D(motion_, 1, GL_RG16F, w, h);
  glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
  glTextureStorage2D(depth_, 1, GL_DEPTH_COMPONENT32F, w, h);
  glCreateFramebuffers(1, &framebuffer_);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, color_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT1, motion_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depth_, 0);
  const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(framebuffer_, 2, buffers);
  Status s = checkGlErrors("MotionTarget::create (out of memory?)");
  const GLenum complete = glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER);
  if (s.isOk() && complete != GL_FRAMEBUFFER_COMPLETE)
    s = {StatusCode::kBackend,
         detail::strCat("MotionTarget: the framebuffer is not complete (status ", complete, ")")};
  width_ = width;
  height_ = height;
  if (!s.isOk()) release();
  return s;
}

void MotionTarget::bind() {
  GLint draw = 0, read = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
  // Bound already (clear() each frame): what was bound before the first bind() stays saved.
  if (GLuint(draw) != framebuffer_ || GLuint(read) != framebuffer_) {
    saved_draw_ = draw;
    saved_read_ = read;
    glGetIntegerv(GL_VIEWPORT, saved_viewport_);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, GLsizei(width_), GLsizei(height_));
}

void MotionTarget::restore() const {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(saved_draw_));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(saved_read_));
  glViewport(saved_viewport_[0], saved_viewport_[1], saved_viewport_[2], saved_viewport_[3]);
}

void MotionTarget::clear(const glm::vec4& color) {
  bind();
  const float none[4] = {0.0f, 0.0f, 0.0f, 0.0f}, far_depth = 1.0f;
  glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, &color[0]);
  glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 1, none);
  glClearNamedFramebufferfv(framebuffer_, GL_DEPTH, 0, &far_depth);
}

namespace {
// Reads level 0 of `texture` (`width` x `height`, `per_pixel` elements of T a pixel, as
// `format` and `type`) into `out`, for the read call `what` of a target created or not
// (`created`).
template <class T>
Status readImage(const char* what, bool created, GLuint texture, uint32_t width, uint32_t height,
                 size_t per_pixel, GLenum format, GLenum type, std::vector<T>* out) {
  detail::takeHostErrors(what);
  if (!created || out == nullptr)
    return {StatusCode::kInvalidArgument, detail::strCat(what, ": create() first, non-null out")};
  const detail::GlStateGuard guard(detail::readbackFootprint(), true);
  out->resize(size_t(width) * height * per_pixel);
  glGetTextureImage(texture, 0, format, type, GLsizei(out->size() * sizeof(T)), out->data());
  return checkGlErrors(what);
}
}  // namespace

Status MotionTarget::readMotion(std::vector<glm::vec2>* out) const {
  return readImage("MotionTarget::readMotion", framebuffer_ != 0, motion_, width_, height_, 1,
                   GL_RG, GL_FLOAT, out);
}

Status MotionTarget::readColor(std::vector<uint8_t>* rgba) const {
  return readImage("MotionTarget::readColor", framebuffer_ != 0, color_, width_, height_, 4,
                   GL_RGBA, GL_UNSIGNED_BYTE, rgba);
}

Status MotionTarget::readDepth(std::vector<float>* out) const {
  return readImage("MotionTarget::readDepth", framebuffer_ != 0, depth_, width_, height_, 1,
                   GL_DEPTH_COMPONENT, GL_FLOAT, out);
}

Status MotionTarget::summarize(MotionSummary* out) const {
  if (out == nullptr)
    return {StatusCode::kInvalidArgument, "MotionTarget::summarize: null out"};
  std::vector<glm::vec2> motion;
  std::vector<float> depth;
  Status s = readMotion(&motion);
  if (s.isOk()) s = readDepth(&depth);
  if (!s.isOk()) return s;
  MotionSummary m;
  double sum = 0.0;
  for (size_t p = 0; p < motion.size(); ++p) {
    if (depth[p] >= 1.0f) continue;
    const double pixels = std::hypot(double(motion[p].x) * width_, double(motion[p].y) * height_);
    ++m.drawn_pixels;
    sum += pixels;
    m.max_pixels = std::max(m.max_pixels, pixels);
  }
  m.mean_pixels = m.drawn_pixels > 0 ? sum / double(m.drawn_pixels) : 0.0;
  *out = m;
  return Status::ok();
}

void MotionTarget::blitColor(uint32_t framebuffer, uint32_t width, uint32_t height) const {
  glNamedFramebufferReadBuffer(framebuffer_, GL_COLOR_ATTACHMENT0);
  glBlitNamedFramebuffer(framebuffer_, framebuffer, 0, 0, GLint(width_), GLint(height_), 0, 0,
                         GLint(width), GLint(height), GL_COLOR_BUFFER_BIT, GL_LINEAR);
}

void MotionTarget::release() {
  if (framebuffer_ == 0 && color_ == 0) return;
  if (glDeleteFramebuffers == nullptr) return;  // No GL loaded: nothing was made.
  glDeleteFramebuffers(1, &framebuffer_);
  const GLuint textures[3] = {color_, motion_, depth_};
  glDeleteTextures(3, textures);
  framebuffer_ = color_ = motion_ = depth_ = 0;
  width_ = height_ = 0;
}

}  // namespace si
