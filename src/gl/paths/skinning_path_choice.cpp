// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The automatic skinning path choice: measured, not guessed.
#include "gl/paths/skinning_path_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "gl/resources/gpu_timer.h"

namespace si::detail {

namespace {

// The synthetic crowd: `n` records of clip 0 halfway between its first two frames, a grid of
// small characters filling clip space (the identity camera), `capacity` per batch of `block`
// bytes, written into the ring region at `base`.
void writeGrid(const DrawResources& r, uint32_t n, size_t base, size_t block,
               std::vector<DrawBatch>* draws) {
  const BakedPalette& palette = *r.palette->palette();
  const uint32_t batches = (n + r.capacity - 1) / r.capacity;
  const BakedClip& clip = palette.clips[0];
  const uint32_t next =
      clip.first_texel + (clip.frame_count > 1 ? palette.layout.frame_stride_texels : 0);
  const float half = 0.5f;
  const uint32_t side = uint32_t(std::ceil(std::sqrt(double(n))));
  const float scale = 1.0f / float(side);
  draws->clear();
  for (uint32_t b = 0; b < batches; ++b) {
    DrawBatch d;
    d.byte_offset = uint32_t(b * block);
    d.instance_count = std::min(r.capacity, n - b * r.capacity);
    for (uint32_t i = 0; i < d.instance_count; ++i) {
      const uint32_t index = b * r.capacity + i;
      InstanceRecord rec{};
      const float x = (float(index % side) + 0.5f) * 2.0f * scale - 1.0f;
      const float y = (float(index / side) + 0.1f) * 2.0f * scale - 1.0f;
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) rec.world_rows[row][col] = row == col ? scale * 0.45f : 0.0f;
      rec.world_rows[0][3] = x;
      rec.world_rows[1][3] = y;
      rec.world_rows[2][3] = 0.0f;
      rec.frames[0] = rec.frames[2] = clip.first_texel;
      rec.frames[1] = rec.frames[3] = next;
      std::memcpy(&rec.blend[0], &half, 4);
      std::memcpy(&rec.blend[1], &half, 4);
      rec.blend[3] = 0xFFFFFFFFu;
      std::memcpy(r.ring->mapped(base) + d.byte_offset + size_t(i) * sizeof(rec), &rec,
                  sizeof(rec));
    }
    draws->push_back(d);
  }
}

}  // namespace

Status chooseSkinningPath(const DrawResources& r, VertexShaderPath& vertex_path,
                          ComputePath& compute_path, const glm::vec3& light, PathChoice* out) {
  const uint32_t nv = r.preskin->lods.empty() || r.preskin->lods[0].empty()
                          ? 0 : r.preskin->lods[0][0].vertex_count;
  const BakedPalette* palette = r.palette->palette();
  if (nv == 0 || palette == nullptr || palette->clips.empty()) {
    out->path = SkinningPath::kVertexShader;
    out->reason = "nothing to measure (empty mesh or palette): the vertex shader by default";
    return Status::ok();
  }
  const uint32_t n = std::clamp<uint32_t>((1u << 20) / nv + 1, 1u, r.capacity * 16);
  const uint32_t batches = (n + r.capacity - 1) / r.capacity;
  const size_t block = (size_t(r.block_size) + r.alignment - 1) / r.alignment * r.alignment;
  Status s = r.ring->reserve(block * batches);
  if (!s.isOk()) return s;
  size_t base = 0;
  s = r.ring->acquire(&base);
  if (!s.isOk()) return s;
  std::vector<DrawBatch> draws;
  writeGrid(r, n, base, block, &draws);
  // A framebuffer of its own.
  GLint previous_fbo = 0, viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_fbo);
  glGetIntegerv(GL_VIEWPORT, viewport);
  GLuint fbo = kNoObject, targets[2] = {kNoObject, kNoObject};
  glCreateFramebuffers(1, &fbo);
  glCreateRenderbuffers(2, targets);
  glNamedRenderbufferStorage(targets[0], GL_RGBA8, 256, 256);
  glNamedRenderbufferStorage(targets[1], GL_DEPTH_COMPONENT24, 256, 256);
  glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, targets[0]);
  glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, targets[1]);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
  glViewport(0, 0, 256, 256);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  PathFrame frame;
  frame.light = light;
  frame.batches = &draws;
  frame.ring_base = base;
  GpuTimer timer;
  timer.create();
  double best[2] = {1e30, 1e30};
  for (int rep = 0; rep < 3 && s.isOk(); ++rep)
    for (int p = 0; p < 2 && s.isOk(); ++p) {
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      DrawStats st;
      timer.begin(true);
      s = p == 0 ? vertex_path.draw(r, frame, &st) : compute_path.draw(r, frame, &st);
      const double ms = timer.end();
      if (rep > 0) best[p] = std::min(best[p], ms);  // Rep 0 warms up.
    }
  timer.release();
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(previous_fbo));
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  glDeleteFramebuffers(1, &fbo);
  glDeleteRenderbuffers(2, targets);
  r.ring->finishFrame();
  if (!s.isOk()) return s;
  out->path = best[1] < best[0] ? SkinningPath::kCompute : SkinningPath::kVertexShader;
  char text[200];
  std::snprintf(text, sizeof text,
                "measured %u instances x %u vertices: vertex shader %.3f ms, compute %.3f ms",
                n, nv, best[0], best[1]);
  out->reason = text;
  return Status::ok();
}

}  // namespace si::detail
