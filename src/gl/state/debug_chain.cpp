// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The chained KHR_debug callback of RendererDesc::debug_messages.
#include "gl/state/debug_chain.h"

#include "core/str_cat.h"
#include "si/core/log.h"

namespace si::detail {

void GLAD_API_PTR DebugChain::callback(GLenum source, GLenum type, GLuint id, GLenum severity,
                                       GLsizei length, const GLchar* message, const void* user) {
  const auto* chain = static_cast<const DebugChain*>(user);
  if (chain != nullptr && chain->previous_ != nullptr)
    chain->previous_(source, type, id, severity, length, message, chain->previous_user_);
  const LogLevel level = type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH
                             ? LogLevel::kError
                         : severity == GL_DEBUG_SEVERITY_MEDIUM ? LogLevel::kWarning
                                                                : LogLevel::kDebug;
  logMessage(level, strCat("GL: ", message));
}

void DebugChain::install() {
  if (installed_) return;
  void* previous = nullptr;
  void* previous_user = nullptr;
  glGetPointerv(GL_DEBUG_CALLBACK_FUNCTION, &previous);
  glGetPointerv(GL_DEBUG_CALLBACK_USER_PARAM, &previous_user);
  previous_ = reinterpret_cast<GLDEBUGPROC>(previous);
  previous_user_ = previous_user;
  previous_output_ = glIsEnabled(GL_DEBUG_OUTPUT);
  glDebugMessageCallback(&callback, this);
  glEnable(GL_DEBUG_OUTPUT);
  installed_ = true;
}

void DebugChain::remove() {
  if (!installed_) return;
  installed_ = false;
  void* current = nullptr;
  void* current_user = nullptr;
  glGetPointerv(GL_DEBUG_CALLBACK_FUNCTION, &current);
  glGetPointerv(GL_DEBUG_CALLBACK_USER_PARAM, &current_user);
  if (current != reinterpret_cast<void*>(&callback) || current_user != this) return;
  glDebugMessageCallback(previous_, previous_user_);
  if (!previous_output_) glDisable(GL_DEBUG_OUTPUT);
}

}  // namespace si::detail
