// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// RendererDesc::debug_messages: the renderer's KHR_debug callback, installed in front of the
// host's and handing it every message first, so the host's callback keeps receiving all of them.

#include <glad/gl.h>

namespace si::detail {

class DebugChain {
 public:
  /// Remembers the installed callback, its user pointer and GL_DEBUG_OUTPUT, then installs the
  /// chained callback (which logs through si::logMessage) and enables GL_DEBUG_OUTPUT. The
  /// object must stay at its address until remove().
  void install();
  /// Puts back what install() found, unless the host installed another callback since (then
  /// its choice stands). Idempotent.
  void remove();

 private:
  static void GLAD_API_PTR callback(GLenum source, GLenum type, GLuint id, GLenum severity,
                                    GLsizei length, const GLchar* message, const void* user);

  bool installed_ = false;
  GLDEBUGPROC previous_ = nullptr;
  const void* previous_user_ = nullptr;
  GLboolean previous_output_ = GL_FALSE;
};

}  // namespace si::detail
