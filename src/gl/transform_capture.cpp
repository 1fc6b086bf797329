// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Renderer::captureSkinnedPositions: the skinning vertex shader's model-space output through
// transform feedback, the GPU side of the GPU-equals-CPU tests.
#include <glad/gl.h>

#include <cstring>
#include <vector>

#include "gl/paths/draw_path.h"
#include "gl/renderer_impl.h"
#include "gl/resources/gl_allocation.h"

namespace si {

Status Renderer::captureSkinnedPositions(const InstanceRecord& record, std::vector<glm::vec3>* out) {
  if (!impl_ || !impl_->ready() || out == nullptr)
    return {StatusCode::kInvalidArgument,
            "captureSkinnedPositions: init, uploads first, and a non-null output"};
  Impl& m = *impl_;
  const uint32_t vertices = m.character.vertex_count;
  GLuint ubo = detail::kNoObject, tf = detail::kNoObject;
  std::vector<uint8_t> block(m.block_size, 0);
  std::memcpy(block.data(), &record, sizeof(record));
  Status s = detail::createBuffer(&ubo, block.size(), block.data(), 0,
                                  "captureSkinnedPositions: the record block");
  if (s.isOk())
    s = detail::createBuffer(&tf, size_t(vertices) * 12, nullptr, GL_MAP_READ_BIT,
                             "captureSkinnedPositions: the capture buffer");
  if (!s.isOk()) {
    glDeleteBuffers(1, &ubo);
    return s;
  }
  Camera identity;  // Model space out: the capture reads positions before the world transform.
  detail::bindShading(m.resources(), m.programs[detail::ProgramId::kCapture], identity,
                      light_direction_);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, ubo);
  glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, tf);
  glEnable(GL_RASTERIZER_DISCARD);
  glBeginTransformFeedback(GL_POINTS);
  glDrawArraysInstanced(GL_POINTS, 0, GLsizei(vertices), 1);
  glEndTransformFeedback();
  glDisable(GL_RASTERIZER_DISCARD);
  out->resize(vertices);
  glGetNamedBufferSubData(tf, 0, GLsizeiptr(size_t(vertices) * 12), out->data());
  glDeleteBuffers(1, &ubo);
  glDeleteBuffers(1, &tf);
  return checkGlErrors("captureSkinnedPositions");
}

}  // namespace si
