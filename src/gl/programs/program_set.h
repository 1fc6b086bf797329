// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Compiling and linking: every program of the catalog (program_catalog.h), built once by
// Renderer::init(), each with the locations of the shared uniforms it declares.

#include <glad/gl.h>

#include <array>
#include <string>

#include "gl/programs/program_catalog.h"
#include "si/core/status.h"

namespace si::detail {

inline constexpr GLuint kNoObject = 0;

/// A linked program and which of the shared uniforms it declares (-1: absent; setting an
/// absent location is GL_INVALID_OPERATION).
struct Program {
  GLuint id = kNoObject;
  GLint view_projection = -1, light_direction = -1, custom_layers = -1;
  /// Motion vectors: the crowd's last and previous update cameras' view-projections.
  GLint motion_view_projection = -1, previous_view_projection = -1;
};

/// Compiles one shader: kBackend with the driver's log on failure.
Status compileShader(GLenum type, const std::string& source, const char* name, GLuint* out);

/// The catalog's programs, compiled and linked.
class ProgramSet {
 public:
  ProgramSet() = default;
  ProgramSet(const ProgramSet&) = delete;
  ProgramSet& operator=(const ProgramSet&) = delete;
  ~ProgramSet() = default;  // release() needs the context: the renderer calls it.

  /// Builds every program of the catalog with `config`'s defines. kBackend with the driver's
  /// log (and nothing kept) when one fails to compile or link.
  Status build(const ShaderConfig& config);
  /// Deletes every program (context current). Idempotent.
  void release();

  const Program& operator[](ProgramId id) const { return programs_[size_t(id)]; }

 private:
  std::array<Program, kProgramCount> programs_{};
};

}  // namespace si::detail
