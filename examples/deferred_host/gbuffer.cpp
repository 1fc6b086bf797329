// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The G-buffer, its material and the host's ground.
#include "deferred_host/gbuffer.h"

#include <glad/gl.h>

#include <string>

#include "deferred_host/gl_program.h"

namespace deferred {

si::MaterialDesc GBuffer::material() {
  si::MaterialDesc d;
  d.name = "deferred G-buffer";
  d.source = R"(
layout(location = 0) out vec4 o_albedo;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_material;
void siMaterial(SiSurface s) {
  o_albedo = vec4(siSurfaceAlbedo(s), s.occlusion);
  o_normal = vec4(s.normal, s.impostor ? 0.5 : 1.0);
  o_material = vec4(s.metallic, s.roughness, 0.0, 1.0);
}
)";
  return d;
}

namespace {

// The ground: a square at y = 0 in camera-relative space (the camera at the origin).
constexpr const char* kGroundVertex = R"(#version 450 core
layout(location = 0) uniform mat4 u_view_projection;  // Camera-relative.
layout(location = 1) uniform vec4 u_ground;  // Camera position xyz, half side.
void main() {
  vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
  vec3 world = vec3(corner.x * u_ground.w, 0.0, corner.y * u_ground.w);
  gl_Position = u_view_projection * vec4(world - u_ground.xyz, 1.0);
}
)";
constexpr const char* kGroundFragment = R"(#version 450 core
layout(location = 0) out vec4 o_albedo;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_material;
void main() {
  o_albedo = vec4(0.32, 0.30, 0.27, 1.0);
  o_normal = vec4(0.0, 1.0, 0.0, 0.25);
  o_material = vec4(0.0, 0.85, 0.0, 1.0);
}
)";

}  // namespace

si::Status GBuffer::init(uint32_t width, uint32_t height) {
  width_ = width;
  height_ = height;
  const GLenum formats[3] = {GL_RGBA16F, GL_RGBA16F, GL_RGBA8};
  glCreateTextures(GL_TEXTURE_2D, 3, colour_);
  for (int t = 0; t < 3; ++t)
    glTextureStorage2D(colour_[t], 1, formats[t], GLsizei(width), GLsizei(height));
  glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
  glTextureStorage2D(depth_, 1, GL_DEPTH_COMPONENT32F, GLsizei(width), GLsizei(height));
  glCreateFramebuffers(1, &framebuffer_);
  for (int t = 0; t < 3; ++t)
    glNamedFramebufferTexture(framebuffer_, GLenum(GL_COLOR_ATTACHMENT0 + t), colour_[t], 0);
  glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depth_, 0);
  const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glNamedFramebufferDrawBuffers(framebuffer_, 3, buffers);
  if (glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    return {si::StatusCode::kBackend, "the G-buffer is incomplete"};
  glCreateVertexArrays(1, &vao_);
  return linkProgram("ground", kGroundVertex, kGroundFragment, &ground_program_);
}

void GBuffer::release() {
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteTextures(3, colour_);
  glDeleteTextures(1, &depth_);
  glDeleteProgram(ground_program_);
  glDeleteVertexArrays(1, &vao_);
  *this = GBuffer();
}

void GBuffer::bindAndClear() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, GLsizei(width_), GLsizei(height_));
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f}, far_depth = 1.0f;
  for (int t = 0; t < 3; ++t) glClearNamedFramebufferfv(framebuffer_, GL_COLOR, t, zero);
  glClearNamedFramebufferfv(framebuffer_, GL_DEPTH, 0, &far_depth);
}

void GBuffer::drawGround(const si::Camera& camera, float half_side) const {
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glUseProgram(ground_program_);
  const glm::mat4 vp = camera.projection * camera.view_rotation;
  glProgramUniformMatrix4fv(ground_program_, 0, 1, GL_FALSE, &vp[0][0]);
  glProgramUniform4f(ground_program_, 1, float(camera.position.x), float(camera.position.y),
                     float(camera.position.z), half_side);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
}

}  // namespace deferred
