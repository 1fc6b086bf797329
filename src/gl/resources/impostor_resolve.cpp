// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// An impostor atlas's level 0 averaged from its supersampled capture, and its mip levels.
#include "gl/resources/impostor_resolve.h"

#include "gl/resources/impostor_atlas.h"
#include "si/gl/gl_context.h"

namespace si::detail {

Status resolveImpostorCapture(GLuint program, GLuint capture, GLuint atlas, uint32_t width,
                              uint32_t height, uint32_t factor) {
  glTextureParameteri(capture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(capture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glUseProgram(program);
  glBindTextureUnit(0, capture);
  glBindImageTexture(0, atlas, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
  glProgramUniform1i(program, 1, GLint(factor));
  const auto dispatch = [&](GLint first_layer, GLint layers, bool codes) {
    glProgramUniform3i(program, 0, GLint(width), GLint(height), first_layer);
    glProgramUniform1i(program, 2, codes ? 1 : 0);
    glDispatchCompute((width + 7) / 8, (height + 7) / 8, GLuint(layers));
  };
  dispatch(0, GLint(ImpostorAtlas::kLayers),
           false);                       // Every layer's means, which the mip levels average.
  glMemoryBarrier(GL_ALL_BARRIER_BITS);  // The mip generation reads what the pass wrote.
  glGenerateTextureMipmap(atlas);
  dispatch(GLint(ImpostorAtlas::kSurfaceLayer), 1, true);  // Then level 0's, one material's.
  glMemoryBarrier(GL_ALL_BARRIER_BITS);  // The coverage and surface read back.
  return checkGlErrors("buildImpostor: resolving the supersampled capture into the atlas");
}

}  // namespace si::detail
