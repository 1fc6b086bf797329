// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A host's framebuffer of two colour targets for the material tests (host materials writing
// two outputs, the metallic-roughness surface probe).
#include <glad/gl.h>

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace si::test {

// The host's framebuffer: two colour targets of one format (GL_RGBA8 by default; both drawn)
// and a depth buffer, bound as the framebuffer with its viewport; with `samples`, multisampled
// (read back resolved).
class TwoTargets {
 public:
  explicit TwoTargets(uint32_t size, GLenum format = GL_RGBA8, GLsizei samples = 0)
      : size_(size), samples_(samples) {
    glCreateFramebuffers(1, &fbo_);
    glCreateTextures(samples > 0 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D, 2, colour_);
    for (GLuint t : colour_) {
      if (samples > 0)
        glTextureStorage2DMultisample(t, samples, format, GLsizei(size), GLsizei(size), GL_TRUE);
      else
        glTextureStorage2D(t, 1, format, GLsizei(size), GLsizei(size));
    }
    glCreateRenderbuffers(1, &depth_);
    glNamedRenderbufferStorageMultisample(depth_, samples, GL_DEPTH_COMPONENT32F, GLsizei(size),
                                          GLsizei(size));
    if (samples > 0) {  // Where read() resolves a target.
      glCreateTextures(GL_TEXTURE_2D, 1, &resolved_);
      glTextureStorage2D(resolved_, 1, format, GLsizei(size), GLsizei(size));
      glCreateFramebuffers(1, &resolve_fbo_);
      glNamedFramebufferTexture(resolve_fbo_, GL_COLOR_ATTACHMENT0, resolved_, 0);
    }
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, colour_[0], 0);
    glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT1, colour_[1], 0);
    glNamedFramebufferRenderbuffer(fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(fbo_, 2, buffers);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, GLsizei(size), GLsizei(size));
  }
  ~TwoTargets() {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo_);
    glDeleteTextures(2, colour_);
    glDeleteRenderbuffers(1, &depth_);
    glDeleteFramebuffers(1, &resolve_fbo_);
    glDeleteTextures(1, &resolved_);
  }
  bool complete() const {
    return glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  }
  // Target 0 to `background` (the fixture's by default), target 1 to zero, depth to 1.
  void clear(glm::vec4 background = glm::vec4(0.2f, 0.25f, 0.3f, 1.0f)) const {
    const float zero[4] = {0, 0, 0, 0}, far = 1.0f;
    glClearNamedFramebufferfv(fbo_, GL_COLOR, 0, &background.x);
    glClearNamedFramebufferfv(fbo_, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(fbo_, GL_DEPTH, 0, &far);
  }
  std::vector<uint8_t> read(int target) const {
    std::vector<uint8_t> rgba(size_t(size_) * size_ * 4);
    glGetTextureImage(single(target), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()),
                      rgba.data());
    return rgba;
  }
  std::vector<glm::vec4> readFloat(int target) const {
    std::vector<glm::vec4> texels(size_t(size_) * size_);
    glGetTextureImage(single(target), 0, GL_RGBA, GL_FLOAT, GLsizei(texels.size() * 16),
                      texels.data());
    return texels;
  }
  // Single-sampled targets only.
  std::vector<float> readDepth() const {
    std::vector<float> depth(size_t(size_) * size_);
    glReadPixels(0, 0, GLsizei(size_), GLsizei(size_), GL_DEPTH_COMPONENT, GL_FLOAT,
                 depth.data());
    return depth;
  }

 private:
  // Target `target` single-sampled: itself, or resolved (a blit of its samples).
  GLuint single(int target) const {
    if (samples_ == 0) return colour_[target];
    glNamedFramebufferReadBuffer(fbo_, GLenum(GL_COLOR_ATTACHMENT0 + target));
    const GLint s = GLint(size_);
    glBlitNamedFramebuffer(fbo_, resolve_fbo_, 0, 0, s, s, 0, 0, s, s, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
    return resolved_;
  }

  uint32_t size_;
  GLsizei samples_;
  GLuint fbo_ = 0, colour_[2] = {0, 0}, depth_ = 0;
  GLuint resolve_fbo_ = 0, resolved_ = 0;
};

}  // namespace si::test
