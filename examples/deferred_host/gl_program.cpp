// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Compiling and linking the example's own programs.
#include "deferred_host/gl_program.h"

#include <glad/gl.h>

#include <string>

namespace deferred {

namespace {

std::string shaderLog(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(length > 1 ? length : 1), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  return log;
}

}  // namespace

si::Status linkProgram(const char* name, const char* vertex, const char* fragment,
                       uint32_t* program) {
  const GLenum types[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
  const char* sources[2] = {vertex, fragment};
  GLuint shaders[2] = {};
  for (int k = 0; k < 2; ++k) {
    shaders[k] = glCreateShader(types[k]);
    glShaderSource(shaders[k], 1, &sources[k], nullptr);
    glCompileShader(shaders[k]);
    GLint ok = 0;
    glGetShaderiv(shaders[k], GL_COMPILE_STATUS, &ok);
    if (!ok) {
      const std::string log = shaderLog(shaders[k]);
      glDeleteShader(shaders[0]);
      if (k == 1) glDeleteShader(shaders[1]);
      return {si::StatusCode::kBackend,
              std::string(name) + (k == 0 ? " vertex" : " fragment") + " shader: " + log};
    }
  }
  const GLuint p = glCreateProgram();
  glAttachShader(p, shaders[0]);
  glAttachShader(p, shaders[1]);
  glLinkProgram(p);
  glDeleteShader(shaders[0]);
  glDeleteShader(shaders[1]);
  GLint linked = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &linked);
  if (!linked) {
    glDeleteProgram(p);
    return {si::StatusCode::kBackend, std::string(name) + ": the program does not link"};
  }
  *program = p;
  return si::Status::ok();
}

}  // namespace deferred
