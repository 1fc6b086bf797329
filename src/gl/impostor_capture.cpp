// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Renderer::buildImpostor: the character drawn into its impostor atlas, one cell per captured
// frame and view direction, by an orthographic camera over the whole grid (one drawCrowd with
// the capture program writing the three layers), into the atlas itself or, supersampled, into a
// capture of its own averaged into the atlas (resources/impostor_resolve.h).
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <iterator>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/str_cat.h"
#include "crowd/impostor_plan.h"
#include "gl/renderer_impl.h"
#include "gl/resources/gl_allocation.h"
#include "gl/resources/impostor_coverage.h"
#include "gl/resources/impostor_resolve.h"
#include "gl/resources/impostor_surface.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/handle_pool.h"
#include "si/crowd/instance_batcher.h"

namespace si {
using detail::strCat;

namespace {

// The capture framebuffer: three layers (the atlas's, or the supersampled capture's own) and a
// depth buffer, deleted with it.
struct CaptureTarget {
  GLuint framebuffer = 0, depth = 0, supersampled = 0;
  ~CaptureTarget() {
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteRenderbuffers(1, &depth);
    glDeleteTextures(1, &supersampled);
  }
  Status create(GLuint layers, GLsizei w, GLsizei h) {
    glCreateRenderbuffers(1, &depth);
    glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT24, w, h);
    glCreateFramebuffers(1, &framebuffer);
    glNamedFramebufferTextureLayer(framebuffer, GL_COLOR_ATTACHMENT0, layers, 0, 0);
    glNamedFramebufferTextureLayer(framebuffer, GL_COLOR_ATTACHMENT1, layers, 0, 1);
    glNamedFramebufferTextureLayer(framebuffer, GL_COLOR_ATTACHMENT2, layers, 0, 2);
    glNamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glNamedFramebufferDrawBuffers(framebuffer, 3, buffers);
    const GLenum complete = glCheckNamedFramebufferStatus(framebuffer, GL_DRAW_FRAMEBUFFER);
    if (complete != GL_FRAMEBUFFER_COMPLETE)
      return {StatusCode::kBackend,
              strCat("buildImpostor: the capture framebuffer is incomplete (0x", std::hex,
                     complete, ")")};
    return checkGlErrors("buildImpostor: the capture framebuffer");
  }
};

}  // namespace

bool Renderer::hasImpostor(CharacterId id) const {
  return impl_ && id.index < impl_->characters.size() &&
         impl_->characters[id.index]->impostor.ready();
}

Status Renderer::buildImpostor(CharacterId id, const ImpostorDesc& desc, ImpostorInfo* info) {
  if (!impl_) return {StatusCode::kInvalidArgument, "Renderer: init() first"};
  Impl& m = *impl_;
  detail::CharacterSlot* slot = nullptr;
  const Status found = m.find(id, "buildImpostor", &slot);
  if (!found.isOk()) return found;
  const Status es =
      m.esRefuses("buildImpostor", "impostor programs (their clip table is a storage buffer)");
  if (!es.isOk()) return es;
  detail::CharacterSlot& c = *slot;
  const BakedPalette& palette = *c.palette.palette();
  const uint32_t sub_meshes = uint32_t(c.character.sub_meshes.size());
  // The atlas is a texture, the capture's depth a renderbuffer, drawn through one viewport.
  const detail::ImpostorSide sides[] = {
      {m.info.max_texture_size, "GL_MAX_TEXTURE_SIZE"},
      {m.info.max_renderbuffer_size, "GL_MAX_RENDERBUFFER_SIZE"},
      {std::min(m.info.max_viewport_width, m.info.max_viewport_height), "GL_MAX_VIEWPORT_DIMS"}};
  detail::ImpostorPlan plan;
  const Status planned = detail::planImpostor(
      palette, sub_meshes, desc, Span<const detail::ImpostorSide>(sides, std::size(sides)), 4,
      "buildImpostor", &plan);
  if (info != nullptr) *info = plan.info;  // Reported before anything is allocated.
  if (!planned.isOk()) return planned;

  detail::GlFootprint footprint = detail::uploadFootprint();
  footprint.pack = true;        // The coverage read back.
  footprint.image_units |= 1u;  // The supersampled capture's resolve.
  const auto guard = m.enter("buildImpostor", footprint, nullptr, true);
  detail::ImpostorAtlas atlas;
  const GLsizei w = GLsizei(plan.info.width), h = GLsizei(plan.info.height);
  Status s =
      detail::createTexture2DArray(&atlas.texture, GLsizei(plan.levels), GL_RGBA8, w, h,
                                   detail::ImpostorAtlas::kLayers, "buildImpostor: the atlas");
  // Supersampled, the capture draws into layers of its own, averaged into the atlas after.
  const uint32_t ss = plan.info.capture_supersample;
  const GLsizei cw = GLsizei(plan.info.width * ss), ch = GLsizei(plan.info.height * ss);
  CaptureTarget target;
  if (s.isOk() && ss > 1)
    s = detail::createTexture2DArray(&target.supersampled, 1, GL_RGBA8, cw, ch,
                                     detail::ImpostorAtlas::kLayers,
                                     "buildImpostor: the supersampled capture");
  const GLuint drawn = ss > 1 ? target.supersampled : atlas.texture;  // The capture's layers.
  if (s.isOk()) s = target.create(drawn, cw, ch);

  // The crowd: one instance per cell, every cell's character at LOD 0.
  CrowdManager crowd;
  Camera camera;
  if (s.isOk()) s = detail::makeCaptureCrowd(plan, palette, sub_meshes, &crowd, &camera);
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(batchLimits());
  if (s.isOk()) {
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    glViewport(0, 0, cw, ch);
    glEnable(GL_DEPTH_TEST);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f}, far_depth = 1.0f;
    for (GLint layer = 0; layer < GLint(detail::ImpostorAtlas::kLayers); ++layer)
      glClearNamedFramebufferfv(target.framebuffer, GL_COLOR, layer, zero);
    glClearNamedFramebufferfv(target.framebuffer, GL_DEPTH, 0, &far_depth);
    const bool motion = m.desc.motion_vectors;
    m.desc.motion_vectors = false;
    m.program_override = detail::ProgramId::kImpostorCapture;
    s = drawCrowd(id, crowd.view(), batcher, camera, nullptr, DrawMode::kSkinned);
    m.program_override = detail::ProgramId::kCount;
    m.desc.motion_vectors = motion;
  }
  if (s.isOk() && ss > 1)
    s = detail::resolveImpostorCapture(m.programs[detail::ProgramId::kImpostorResolve].id,
                                       target.supersampled, atlas.texture, plan.info.width,
                                       plan.info.height, ss);
  else if (s.isOk())
    glGenerateTextureMipmap(atlas.texture);
  if (s.isOk()) {
    glTextureParameteri(atlas.texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(atlas.texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(atlas.texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(atlas.texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameterf(atlas.texture, GL_TEXTURE_LOD_BIAS, desc.lod_bias);
    s = checkGlErrors("buildImpostor: the atlas's mip levels");
  }
  // The clip table, then every cell's covered rectangle at every level (the quads' extent).
  std::vector<uint32_t> rects;
  if (s.isOk())
    s = detail::measureCoveredRects(atlas.texture, plan.columns, plan.rows, plan.cell, plan.levels,
                                    &rects);
  // The surface's one value, where the capture drew texels whole (the averaged atlas's edges
  // hold it times their coverage).
  if (s.isOk())
    s = detail::measureUniformSurface(drawn, uint32_t(cw), uint32_t(ch), &atlas.uniform_surface);
  if (s.isOk()) {
    const std::vector<uint32_t> table = detail::impostorClipTable(plan, rects);
    s = detail::createBuffer(&atlas.clips, table.size() * sizeof(uint32_t), table.data(), 0,
                             "buildImpostor: the clip table");
  }
  if (!s.isOk()) {
    atlas.release();
    return s;
  }
  static_cast<detail::ImpostorGrid&>(atlas) = detail::impostorGrid(plan, palette);
  if (info != nullptr) info->uniform_surface = atlas.uniform_surface != 0;
  c.impostor.release();
  c.impostor = atlas;
  return m.check("buildImpostor");
}

}  // namespace si
