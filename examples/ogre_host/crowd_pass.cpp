// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "ogre_host/crowd_pass.h"

#include <glad/gl.h>

#include <Ogre.h>

#include "si/core/default_character.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/gl_context.h"
#include "si/gl/material.h"

namespace si::ogre_host {

namespace {

// Lambert under OGRE's light: the host's uniform block at binding 7 holds the light's direction
// (world, travelling), its diffuse colour and the scene's ambient colour.
constexpr const char* kOgreLit = R"(
layout(location = 0) out vec4 o_color;
layout(std140, binding = 7) uniform OgreLight {
  vec4 ogre_direction;
  vec4 ogre_diffuse;
  vec4 ogre_ambient;
};
void siMaterial(SiSurface s) {
  float lambert = max(dot(s.normal, -ogre_direction.xyz), 0.0);
  vec3 albedo = siSurfaceAlbedo(s);
  o_color = vec4(albedo * (ogre_ambient.rgb + ogre_diffuse.rgb * lambert), 1.0);
})";

glm::mat4 toGlm(const Ogre::Matrix4& m) {
  glm::mat4 out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[c][r] = float(m[r][c]);
  return out;
}

}  // namespace

Status CrowdPass::init(void* (*get_proc)(void*, const char*), uint32_t count) {
  GlInfo info;
  Status s = loadGl(get_proc, nullptr, &info);
  if (s.isOk()) s = makeDefaultCharacter({}, &character_);
  BakeDesc bake;
  bake.rate_mode = RateMode::kFixed;
  bake.sample_rate_hz = 30.0f;
  if (s.isOk()) s = bakePalette(character_, bake, &palette_, nullptr);
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  if (s.isOk()) s = renderer_.init(info, rd);
  CharacterId id;
  if (s.isOk()) s = renderer_.addCharacter(character_, palette_, &id);
  MaterialDesc md;
  md.name = "OGRE's light";
  md.source = kOgreLit;
  MaterialId material;
  if (s.isOk()) s = renderer_.addMaterial(md, &material);
  if (s.isOk()) s = renderer_.setMaterial(id, material);
  if (s.isOk()) s = batcher_.init(renderer_.batchLimits());
  CrowdDesc cd;
  cd.palette = &palette_;
  cd.sub_mesh_count = uint32_t(character_.mesh.sub_meshes.size());
  cd.lod_count = 3;
  if (s.isOk()) s = crowd_.init(cd);
  for (uint32_t k = 0; k < count && s.isOk(); ++k) {
    InstanceDesc d;
    const uint32_t columns = 8;
    d.position = glm::dvec3((double(k % columns) - 3.5) * 1.2, 0.0, -2.0 - 1.5 * double(k / columns));
    d.clip = k % uint32_t(palette_.clips.size());
    d.time_seconds = 0.17 * k;
    d.speed = 0.0f;  // Every frame the same pose: the frames compare pixel for pixel.
    d.variation_mask = 1u | ((k * 5u) << 1);
    d.color = glm::u8vec4(uint8_t(60 + 23 * k), uint8_t(200 - 11 * k), uint8_t(90 + 37 * (k % 4)), 255);
    InstanceHandle h;
    s = crowd_.add(d, &h);
  }
  if (s.isOk()) glCreateBuffers(1, &light_block_);
  if (s.isOk()) glNamedBufferStorage(light_block_, 48, nullptr, GL_DYNAMIC_STORAGE_BIT);
  return s;
}

void CrowdPass::enable(Ogre::Camera* camera, Ogre::Light* light, bool on) {
  camera_ = camera;
  light_ = light;
  on_ = on;
}

Camera CrowdPass::camera() const {
  const Ogre::Affine3 view = camera_->getViewMatrix();
  glm::dmat4 v(1.0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) v[c][r] = double(view[r][c]);
  const Ogre::Viewport* viewport = camera_->getViewport();
  return Camera::fromMatrices(v, toGlm(camera_->getProjectionMatrix()),
                              DepthConvention::kNegativeOneToOne,
                              float(viewport ? viewport->getActualHeight() : 1080));
}

void CrowdPass::renderQueueEnded(uint8_t queue_group, const std::string& invocation,
                                 bool& repeat) {
  (void)invocation;
  repeat = false;
  if (!on_ || queue_group != Ogre::RENDER_QUEUE_MAIN || !error_.isOk()) return;
  const Camera c = camera();
  Status s = crowd_.update(0.0, c);
  // OGRE's light into the host's block at binding 7, which the pass puts back afterwards.
  const Ogre::Vector3 d = light_->getDerivedDirection();
  const Ogre::ColourValue diffuse = light_->getDiffuseColour();
  const Ogre::ColourValue ambient = camera_->getSceneManager()->getAmbientLight();
  const float block[12] = {float(d.x),  float(d.y),  float(d.z),  0.0f,
                           diffuse.r,   diffuse.g,   diffuse.b,   1.0f,
                           ambient.r,   ambient.g,   ambient.b,   1.0f};
  glNamedBufferSubData(light_block_, 0, sizeof(block), block);
  GLint previous = 0;
  glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, 7, &previous);
  glBindBufferBase(GL_UNIFORM_BUFFER, 7, light_block_);
  if (s.isOk()) s = renderer_.drawCrowd(si::CharacterId{}, crowd_.view(), batcher_, c, &stats_);
  glBindBufferBase(GL_UNIFORM_BUFFER, 7, GLuint(previous));
  if (!s.isOk()) error_ = s;
}

Status CrowdPass::coverage(uint32_t width, uint32_t height, std::vector<uint8_t>* mask) {
  GLuint fbo = 0, colour = 0, depth = 0;
  glCreateFramebuffers(1, &fbo);
  glCreateRenderbuffers(1, &colour);
  glCreateRenderbuffers(1, &depth);
  glNamedRenderbufferStorage(colour, GL_RGBA8, GLsizei(width), GLsizei(height));
  glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT24, GLsizei(width), GLsizei(height));
  glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
  glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
  GLint framebuffer = 0, viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  glGetIntegerv(GL_VIEWPORT, viewport);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, GLsizei(width), GLsizei(height));
  renderer_.clear(glm::vec4(0.0f));
  glBindBufferBase(GL_UNIFORM_BUFFER, 7, light_block_);
  const Status s =
      renderer_.drawCrowd(si::CharacterId{}, crowd_.view(), batcher_, camera(), nullptr);
  std::vector<uint8_t> rgba(size_t(width) * height * 4);
  glReadPixels(0, 0, GLsizei(width), GLsizei(height), GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glBindFramebuffer(GL_FRAMEBUFFER, GLuint(framebuffer));
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  glDeleteFramebuffers(1, &fbo);
  glDeleteRenderbuffers(1, &colour);
  glDeleteRenderbuffers(1, &depth);
  mask->assign(size_t(width) * height, 0);
  for (size_t p = 0; p < mask->size(); ++p)  // Rows from the bottom, as glReadPixels gives.
    (*mask)[p] = rgba[p * 4 + 3] != 0 ? 1 : 0;
  return s;
}

void CrowdPass::shutdown() {
  if (light_block_ != 0) glDeleteBuffers(1, &light_block_);
  light_block_ = 0;
  renderer_.shutdown();
}

}  // namespace si::ogre_host
