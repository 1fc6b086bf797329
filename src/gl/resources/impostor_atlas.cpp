// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The impostor atlas's binding and uniforms.
#include "gl/resources/impostor_atlas.h"

namespace si::detail {

void ImpostorAtlas::bind(const Program& program, const Camera& camera, bool quads_computed) const {
  glBindTextureUnit(3, texture);
  const GLuint p = program.id;
  glProgramUniform4ui(p, 40, columns, rows, azimuths, elevations);
  const glm::vec4 viewer = impostorViewer(camera);
  glProgramUniform4f(p, 44, viewer.x, viewer.y, viewer.z, viewer.w);
  if (program.impostor_surface >= 0) {  // w 0: the layer varies, read per fragment.
    const uint32_t u = uniform_surface;
    glProgramUniform4f(p, program.impostor_surface, float(u & 0xFFu) / 255.0f,
                       float((u >> 8) & 0xFFu) / 255.0f, float((u >> 16) & 0xFFu) / 255.0f,
                       float(u >> 24) / 255.0f);
  }
  if (quads_computed) return;
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, clips);
  glProgramUniform4ui(p, 41, clip_count, frame_stride_texels, azimuths * elevations, levels);
  glProgramUniform4fv(p, 42, 1, elevations_radians);
  glProgramUniform4f(p, 43, centre.x, centre.y, centre.z, cell_units);
  // Half the viewport in pixels (a clip-space unit's pixels) and the cell's texels.
  GLint viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, viewport);
  glProgramUniform3f(p, 45, 0.5f * float(viewport[2]), 0.5f * float(viewport[3]),
                     float(cell_texels));
}

void ImpostorAtlas::release() {
  glDeleteTextures(1, &texture);
  glDeleteBuffers(1, &clips);
  *this = ImpostorAtlas();
}

}  // namespace si::detail
