#include "si/crowd/crowd_export.h"
// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "demo_shadows.h"

#include <glad/gl.h>

#include <string>

#include "common/cascades.h"

namespace demo {

namespace {

// The ground: a square of two triangles from gl_VertexID, camera-relative; each fragment finds
// the first cascade that holds it and compares its depth (3x3 percentage-closer filter).
const char* kGroundVertex = R"(#version 450 core
uniform mat4 u_view_projection;
uniform vec3 u_centre;   // Camera-relative.
uniform float u_radius;
out vec3 v_rel;          // Camera-relative world position.
void main() {
  const vec2 corners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
  vec2 c = corners[gl_VertexID] * u_radius;
  v_rel = u_centre + vec3(c.x, 0.0, c.y);
  gl_Position = u_view_projection * vec4(v_rel, 1.0);
}
)";
const char* kGroundFragment = R"(#version 450 core
uniform sampler2DArray u_shadow;
uniform mat4 u_light_vp[3];
uniform vec3 u_light_offset[3];  // Main camera position minus each light camera's.
uniform vec3 u_light_direction;
in vec3 v_rel;
layout(location = 0) out vec4 o_color;
void main() {
  float lit = 1.0;
  for (int c = 0; c < 3; ++c) {
    vec4 clip = u_light_vp[c] * vec4(v_rel + u_light_offset[c], 1.0);
    vec3 p = clip.xyz / clip.w * 0.5 + 0.5;
    if (any(lessThan(p.xy, vec2(0.002))) || any(greaterThan(p.xy, vec2(0.998)))) continue;
    vec2 texel = 1.0 / vec2(textureSize(u_shadow, 0).xy);
    float sum = 0.0;
    for (int y = -1; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x)
        sum += texture(u_shadow, vec3(p.xy + vec2(x, y) * texel, float(c))).r + 0.0015 < p.z ? 0.0 : 1.0;
    lit = sum / 9.0;
    break;
  }
  float n_dot_l = max(dot(vec3(0.0, 1.0, 0.0), -normalize(u_light_direction)), 0.0);
  vec3 ground = vec3(0.55, 0.6, 0.5);
  o_color = vec4(ground * (0.45 + 0.55 * n_dot_l * lit), 1.0);
}
)";

si::Status compileProgram(uint32_t* out) {
  const char* sources[2] = {kGroundVertex, kGroundFragment};
  const GLenum types[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
  const GLuint program = glCreateProgram();
  for (int k = 0; k < 2; ++k) {
    const GLuint s = glCreateShader(types[k]);
    glShaderSource(s, 1, &sources[k], nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[2048] = {};
      glGetShaderInfoLog(s, sizeof log, nullptr, log);
      glDeleteShader(s);
      glDeleteProgram(program);
      return {si::StatusCode::kBackend, std::string("ground shader: ") + log};
    }
    glAttachShader(program, s);
    glDeleteShader(s);
  }
  glLinkProgram(program);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) {
    glDeleteProgram(program);
    return {si::StatusCode::kBackend, "ground program: link failed"};
  }
  *out = program;
  return si::Status::ok();
}

}  // namespace

si::Status CascadedShadows::initGl() {
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &texture_);
  glTextureStorage3D(texture_, 1, GL_DEPTH_COMPONENT32F, GLsizei(kResolution),
                     GLsizei(kResolution), GLsizei(kCascades));
  glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glCreateFramebuffers(GLsizei(kCascades), framebuffers_);
  for (uint32_t c = 0; c < kCascades; ++c) {
    glNamedFramebufferTextureLayer(framebuffers_[c], GL_DEPTH_ATTACHMENT, texture_, 0, GLint(c));
    glNamedFramebufferDrawBuffer(framebuffers_[c], GL_NONE);
    glNamedFramebufferReadBuffer(framebuffers_[c], GL_NONE);
    if (glCheckNamedFramebufferStatus(framebuffers_[c], GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      return {si::StatusCode::kBackend, "shadow map framebuffer incomplete"};
  }
  glCreateVertexArrays(1, &vao_);
  return compileProgram(&program_);
}

void CascadedShadows::releaseGl() {
  views_.clear();
  if (texture_ != 0) glDeleteTextures(1, &texture_);
  if (framebuffers_[0] != 0) glDeleteFramebuffers(GLsizei(kCascades), framebuffers_);
  if (vao_ != 0) glDeleteVertexArrays(1, &vao_);
  if (program_ != 0) glDeleteProgram(program_);
  texture_ = program_ = vao_ = 0;
  for (uint32_t& f : framebuffers_) f = 0;
}

si::Status CascadedShadows::attach(si::CrowdManager& crowd) {
  views_.clear();
  views_.resize(kCascades);
  si::CrowdViewDesc shadow;
  shadow.lod_bias = 1;               // One LOD coarser in the shadow maps.
  shadow.max_distance_radii = -1.0f; // Each cascade's frustum is its far line.
  for (si::CrowdView& v : views_) {
    const si::Status s = v.init(crowd, shadow);
    if (!s.isOk()) return s;
  }
  return si::Status::ok();
}

si::Status CascadedShadows::render(si::Renderer& renderer, const si::InstanceBatcher& batcher,
                                   const si::Camera& camera, const glm::dvec3& centre,
                                   double radius) {
  const glm::mat4& v = camera.view_rotation;
  const glm::dvec3 forward = -glm::dvec3(v[0][2], v[1][2], v[2][2]);
  const double depth = glm::dot(centre - camera.position, forward);
  const double near_m = std::max(0.5, depth - radius), far_m = std::max(near_m * 2.0, depth + radius);
  // The cascades fit the height range the crowd stands in: the ground (at the crowd's centre
  // height) up to two character radii above it.
  const double character = double(si::CrowdExport::cullParams(views_[0], camera).radius);
  lights_ = si::examples::cascadeCameras(camera, kCascades, sunDirection(), float(kResolution),
                                         near_m, far_m, centre.y - character,
                                         centre.y + 2.0 * character);
  GLint framebuffer = 0, viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  glGetIntegerv(GL_VIEWPORT, viewport);
  drawn_ = 0;
  si::Status s = si::Status::ok();
  for (uint32_t c = 0; c < kCascades && s.isOk(); ++c) {
    s = views_[c].select(lights_[c]);
    if (!s.isOk()) break;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffers_[c]);
    glViewport(0, 0, GLsizei(kResolution), GLsizei(kResolution));
    const float far_depth = 1.0f;
    glClearNamedFramebufferfv(framebuffers_[c], GL_DEPTH, 0, &far_depth);
    si::DrawStats stats;
    s = renderer.drawCrowd(si::CharacterId{}, views_[c], batcher, lights_[c], &stats,
                           si::DrawMode::kDepthOnly);
    drawn_ += views_[c].stats().visible;
  }
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(framebuffer));
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  return s;
}

si::Status CascadedShadows::drawGround(const si::Camera& camera, const glm::dvec3& centre,
                                       double radius, const glm::vec3& light_direction) {
  if (lights_.size() != kCascades) return si::Status::ok();  // No shadow map yet.
  glUseProgram(program_);
  const glm::mat4 vp = camera.viewProjection();
  glProgramUniformMatrix4fv(program_, glGetUniformLocation(program_, "u_view_projection"), 1,
                            GL_FALSE, &vp[0][0]);
  const glm::vec3 rel_centre(centre - camera.position);
  glProgramUniform3fv(program_, glGetUniformLocation(program_, "u_centre"), 1, &rel_centre[0]);
  glProgramUniform1f(program_, glGetUniformLocation(program_, "u_radius"), float(radius));
  glm::mat4 light_vp[kCascades];
  glm::vec3 offset[kCascades];
  for (uint32_t c = 0; c < kCascades; ++c) {
    light_vp[c] = lights_[c].viewProjection();
    offset[c] = glm::vec3(camera.position - lights_[c].position);
  }
  glProgramUniformMatrix4fv(program_, glGetUniformLocation(program_, "u_light_vp"),
                            GLsizei(kCascades), GL_FALSE, &light_vp[0][0][0]);
  glProgramUniform3fv(program_, glGetUniformLocation(program_, "u_light_offset"),
                      GLsizei(kCascades), &offset[0][0]);
  glProgramUniform3fv(program_, glGetUniformLocation(program_, "u_light_direction"), 1,
                      &light_direction[0]);
  glProgramUniform1i(program_, glGetUniformLocation(program_, "u_shadow"), 0);
  glBindTextureUnit(0, texture_);
  glBindVertexArray(vao_);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDrawArrays(GL_TRIANGLES, 0, 6);
  glBindVertexArray(0);
  glUseProgram(0);
  return glGetError() == GL_NO_ERROR ? si::Status::ok()
                                     : si::Status(si::StatusCode::kBackend, "drawing the ground");
}

}  // namespace demo
