// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The shader files of src/gl/shaders, embedded at build time with their includes expanded
// (cmake/SiEmbedGlsl.cmake generates the table).

#include <cstddef>

namespace si::detail {

struct EmbeddedShader {
  const char* name;    ///< File name in src/gl/shaders, e.g. "skinned.vert.glsl".
  const char* source;  ///< Its text, every `#include "x"` replaced by x's text.
};
extern const EmbeddedShader kEmbeddedShaders[];
extern const size_t kEmbeddedShaderCount;

/// The expanded text of shader file `name`, or null when there is none.
const char* embeddedShader(const char* name);

}  // namespace si::detail
