// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Renderer's private state: the programs, the uploaded resources and one object per draw path.
// renderer.cpp dispatches to the paths; each path lives in src/gl/paths/.

#include <glad/gl.h>

#include <chrono>
#include <string>
#include <vector>

#include "gl/paths/compute_path.h"
#include "gl/paths/cpu_skinning_path.h"
#include "gl/paths/gpu_culled_path.h"
#include "gl/paths/traditional_path.h"
#include "gl/paths/vertex_shader_path.h"
#include "gl/programs/program_set.h"
#include "gl/resources/character_buffers.h"
#include "gl/resources/gpu_timer.h"
#include "gl/resources/palette_texture.h"
#include "gl/resources/preskin_lists.h"
#include "gl/resources/record_ring.h"
#include "si/gl/renderer.h"

namespace si {

struct Renderer::Impl {
  GlInfo info;
  RendererDesc desc;
  bool debug = false;
  uint32_t block_size = 0, capacity = 0, alignment = 256;
  detail::ProgramSet programs;
  detail::PaletteTexture palette;
  detail::CharacterBuffers character;
  detail::PreSkinLists preskin;
  detail::RecordRing ring;
  detail::GpuTimer timer;
  detail::VertexShaderPath vertex_path;
  detail::ComputePath compute_path;
  detail::TraditionalPath traditional_path;
  detail::CpuSkinningPath cpu_path;
  detail::GpuCulledPath gpu_culled_path;
  std::vector<DrawBatch> batches;  // The batcher's draws of the current frame.
  SkinningPath path = SkinningPath::kVertexShader;
  std::string path_reason = "explicit setting";
  GLuint custom_texture = detail::kNoObject;  // Renderer::setCustomTextureArray.
  uint32_t custom_layers = 0;

  Status check(const char* what) const { return debug ? checkGlErrors(what) : Status::ok(); }
  bool ready() const { return character.ready() && palette.ready(); }

  detail::DrawResources resources() {
    detail::DrawResources r;
    r.info = &info;
    r.desc = &desc;
    r.programs = &programs;
    r.palette = &palette;
    r.character = &character;
    r.preskin = &preskin;
    r.ring = &ring;
    r.block_size = block_size;
    r.capacity = capacity;
    r.alignment = alignment;
    r.custom_texture = custom_texture;
    r.custom_layers = custom_layers;
    return r;
  }

  /// A crowd-only path (no batcher, no mode) for `crowd` seen by `camera`: runPath(), the error
  /// check named `what`, and the stats (when non-null).
  Status drawCrowdOnly(detail::DrawPath& p, const char* what, const CrowdManager& crowd,
                       const Camera& camera, const glm::vec3& light, DrawStats* stats) {
    const auto t0 = std::chrono::steady_clock::now();
    detail::PathFrame frame;
    frame.crowd = &crowd;
    frame.camera = camera;
    frame.light = light;
    DrawStats st;
    Status s = runPath(p, frame, t0, stats != nullptr, &st);
    if (s.isOk()) s = check(what);
    if (stats != nullptr) *stats = st;
    return s;
  }

  /// Runs `p` for `frame`: its uploads, then its commands with depth test and back-face culling
  /// under the GPU timer (when asked for and `stats` is non-null). Fills `st` with what it drew,
  /// the CPU milliseconds since `t0` and the GPU milliseconds.
  Status runPath(detail::DrawPath& p, const detail::PathFrame& frame,
                 std::chrono::steady_clock::time_point t0, bool timed, DrawStats* st) {
    const detail::DrawResources r = resources();
    Status s = p.uploadFrame(r, frame);
    if (!s.isOk()) return s;
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    timer.begin(desc.measure_gpu_time && timed);
    s = p.draw(r, frame, st);
    st->cpu_submit_ms = detail::msSince(t0);  // Before the (blocking) timer read.
    st->gpu_ms = timer.end();
    const GLenum reset = glGetGraphicsResetStatus();
    if (reset != GL_NO_ERROR)
      return {StatusCode::kBackend,
              reset == GL_GUILTY_CONTEXT_RESET     ? "the GL context was lost (reset, caused here)"
              : reset == GL_INNOCENT_CONTEXT_RESET ? "the GL context was lost (reset elsewhere)"
                                                   : "the GL context was lost (reset)"};
    return s;
  }
};

}  // namespace si
