// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Renderer::captureSkinnedPositions: the skinned model-space positions of one instance as
// either skinning path computes them (the vertex shader's output through transform feedback,
// or the compute pre-skinning pass's buffer), the GPU side of the GPU-equals-CPU tests.
#include <glad/gl.h>

#include <cstring>
#include <numeric>
#include <vector>

#include "gl/paths/compute_path.h"
#include "gl/paths/draw_path.h"
#include "gl/renderer_impl.h"
#include "gl/resources/gl_allocation.h"

namespace si {
namespace {

// Buffers the capture creates, deleted on every way out.
struct CaptureBuffers {
  GLuint block = detail::kNoObject, out = detail::kNoObject, list = detail::kNoObject;
  ~CaptureBuffers() {
    const GLuint all[] = {block, out, list};
    for (GLuint b : all)
      if (b != detail::kNoObject) glDeleteBuffers(1, &b);
  }
};

// The vertex shader path: every vertex drawn as a point, its model-space position captured.
void captureVertexShader(const detail::DrawResources& r, uint32_t vertices,
                         const glm::vec3& light, const CaptureBuffers& b) {
  Camera identity;  // Model space out: the capture reads positions before the world transform.
  detail::bindShading(r, r.programs[detail::ProgramId::kCapture], identity, light);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, b.block);
  glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, b.out);
  glEnable(GL_RASTERIZER_DISCARD);
  glBeginTransformFeedback(GL_POINTS);
  glDrawArraysInstanced(GL_POINTS, 0, GLsizei(vertices), 1);
  glEndTransformFeedback();
  glDisable(GL_RASTERIZER_DISCARD);
}

// The compute path: its skinning pass over a vertex list of every vertex in mesh order, for one
// instance whose world transform is the identity (so the camera-relative world position it
// writes is the model-space position).
Status captureCompute(const detail::DrawResources& r, uint32_t vertices, const CaptureBuffers& b) {
  const detail::Program& skin = r.programs[detail::ProgramId::kComputeSkin];
  glUseProgram(skin.id);
  detail::bindPreSkinning(r, b.out, b.list);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, b.block);
  glProgramUniform4ui(skin.id, 5, 0, vertices, 0, 0);
  glProgramUniform2ui(skin.id, 6, 1, r.preskin->source_words);
  const Status s = detail::dispatchGroups(*r.info, (uint64_t(vertices) + 63) / 64,
                                          "captureSkinnedPositions");
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  return s;
}

}  // namespace

Status Renderer::captureSkinnedPositions(CharacterId id, const InstanceRecord& record,
                                         std::vector<glm::vec3>* out, SkinningPath path) {
  if (!impl_ || out == nullptr)
    return {StatusCode::kInvalidArgument,
            "captureSkinnedPositions: init, uploads first, and a non-null output"};
  Impl& m = *impl_;
  detail::CharacterSlot* c = nullptr;
  Status found = m.find(id, "captureSkinnedPositions", &c);
  if (found.isOk())
    found = m.esRefuses("captureSkinnedPositions", "capture programs (desktop GLSL only)");
  if (!found.isOk()) return found;
  if (path == SkinningPath::kAutomatic) path = c->path;
  if (path == SkinningPath::kCompute && m.programs[detail::ProgramId::kComputeSkin].id == 0)
    return {StatusCode::kUnsupported,
            "captureSkinnedPositions: the compute skinning program is not available"};
  const uint32_t vertices = c->character.vertex_count;
  const bool compute = path == SkinningPath::kCompute;
  CaptureBuffers b;
  std::vector<uint8_t> block(m.block_size, 0);
  InstanceRecord r = record;
  if (compute) {
    // Identity world rows: the pass writes world positions; the capture returns model space.
    std::memset(r.world_rows, 0, sizeof(r.world_rows));
    r.world_rows[0][0] = r.world_rows[1][1] = r.world_rows[2][2] = 1.0f;
  }
  std::memcpy(block.data(), &r, sizeof(r));
  Status s = detail::createBuffer(&b.block, block.size(), block.data(), 0,
                                  "captureSkinnedPositions: the record block");
  if (s.isOk())
    s = detail::createBuffer(&b.out, size_t(vertices) * (compute ? 16 : 12), nullptr,
                             GL_MAP_READ_BIT, "captureSkinnedPositions: the capture buffer");
  if (s.isOk() && compute) {
    std::vector<uint32_t> list(vertices);
    std::iota(list.begin(), list.end(), 0u);
    s = detail::createBuffer(&b.list, list.size() * 4, list.data(), 0,
                             "captureSkinnedPositions: the vertex list");
  }
  if (!s.isOk()) return s;
  const auto guard = m.enter("captureSkinnedPositions", detail::captureFootprint(), nullptr, true);
  out->resize(vertices);
  if (compute) {
    s = captureCompute(m.resources(*c), vertices, b);
    if (!s.isOk()) return s;
    std::vector<glm::vec4> skinned(vertices);
    glGetNamedBufferSubData(b.out, 0, GLsizeiptr(size_t(vertices) * 16), skinned.data());
    for (uint32_t v = 0; v < vertices; ++v) (*out)[v] = glm::vec3(skinned[v]);
  } else {
    captureVertexShader(m.resources(*c), vertices, light_direction_, b);
    glGetNamedBufferSubData(b.out, 0, GLsizeiptr(size_t(vertices) * 12), out->data());
  }
  return checkGlErrors("captureSkinnedPositions");
}

}  // namespace si
