// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Buffer and texture storage with named errors.
#include "gl/resources/gl_allocation.h"

#include <algorithm>
#include <limits>
#include <string>

#include "core/str_cat.h"
#include "gl/host_errors.h"
#include "gl/profile/gl_profile.h"
#include "si/gl/gl_context.h"

namespace si::detail {

namespace {

// The errors an allocation raised after its first (a lost context can report errors forever).
void drainErrors() {
  for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
  }
}

// The first error after an allocation, as a status naming it.
Status allocationStatus(const char* what, const std::string& size) {
  const GLenum e = glGetError();
  drainErrors();
  if (e == GL_NO_ERROR) return Status::ok();
  if (e == GL_OUT_OF_MEMORY)
    return {StatusCode::kLimitExceeded,
            strCat(what, ": the GL driver is out of memory for ", size, " (GL_OUT_OF_MEMORY)")};
  return {StatusCode::kBackend, strCat(what, ": ", glErrorName(e), " allocating ", size)};
}

// Replaces `*buffer` by a new buffer whose storage `allocate` makes, with the errors named.
template <typename Allocate>
Status makeBuffer(GLuint* buffer, uint64_t bytes, const char* what, Allocate allocate) {
  if (*buffer != kNoObject) glDeleteBuffers(1, buffer);
  *buffer = kNoObject;
  if (bytes > uint64_t(std::numeric_limits<GLsizeiptr>::max()))
    return {StatusCode::kLimitExceeded, strCat(what, ": ", bytes, " bytes do not fit a GL size")};
  takeHostErrors(what);  // So that the status names only the allocation's error.
  glCreateBuffers(1, buffer);
  allocate(*buffer, GLsizeiptr(bytes));
  Status s = allocationStatus(what, strCat(bytes, " bytes"));
  if (!s.isOk()) {
    glDeleteBuffers(1, buffer);
    *buffer = kNoObject;
  }
  return s;
}

// Replaces `*texture` by a new texture of `target` whose storage `allocate` sets; fails as
// createBuffer() does, naming `size`, and leaves no texture behind.
template <typename Allocate>
Status makeTexture(GLuint* texture, GLenum target, const char* what, const std::string& size,
                   const Allocate& allocate) {
  if (*texture != kNoObject) glDeleteTextures(1, texture);
  *texture = kNoObject;
  takeHostErrors(what);
  glCreateTextures(target, 1, texture);
  allocate(*texture);
  Status s = allocationStatus(what, size);
  if (!s.isOk()) {
    glDeleteTextures(1, texture);
    *texture = kNoObject;
  }
  return s;
}

}  // namespace

Status createBuffer(GLuint* buffer, uint64_t bytes, const void* data, GLbitfield flags,
                    const char* what) {
  return makeBuffer(buffer, bytes, what, [&](GLuint b, GLsizeiptr size) {
    glNamedBufferStorage(b, size, data, flags);
  });
}

Status createIndexBuffer(GLuint* buffer, uint64_t bytes, const void* data, const char* what) {
  return makeBuffer(buffer, bytes, what, [&](GLuint b, GLsizeiptr size) {
    esMarkIndexBuffer(b);
    glNamedBufferStorage(b, size, data, 0);
  });
}

Status createMutableBuffer(GLuint* buffer, uint64_t bytes, GLenum usage, const char* what) {
  return makeBuffer(buffer, bytes, what, [&](GLuint b, GLsizeiptr size) {
    glNamedBufferData(b, size, nullptr, usage);
  });
}

Status createTexture2D(GLuint* texture, GLsizei levels, GLenum internal_format, GLsizei width,
                       GLsizei height, const char* what) {
  return makeTexture(texture, GL_TEXTURE_2D, what, strCat(width, " x ", height, " texels"),
                     [&](GLuint t) { glTextureStorage2D(t, levels, internal_format, width, height); });
}

Status createTexture2DMultisample(GLuint* texture, GLsizei samples, GLenum internal_format,
                                  GLsizei width, GLsizei height, const char* what) {
  return makeTexture(texture, GL_TEXTURE_2D_MULTISAMPLE, what,
                     strCat(width, " x ", height, " texels of ", samples, " samples"),
                     [&](GLuint t) {
                       glTextureStorage2DMultisample(t, samples, internal_format, width, height,
                                                     GL_TRUE);
                     });
}

Status createTexture2DArray(GLuint* texture, GLsizei levels, GLenum internal_format,
                            GLsizei width, GLsizei height, GLsizei layers, const char* what) {
  return makeTexture(texture, GL_TEXTURE_2D_ARRAY, what,
                     strCat(width, " x ", height, " x ", layers, " texels"), [&](GLuint t) {
                       glTextureStorage3D(t, levels, internal_format, width, height, layers);
                     });
}

Status TableBuffer::upload(const std::vector<int32_t>& table, GLuint binding, const char* what) {
  if (buffer == kNoObject || table != content) {
    content.clear();
    const Status s = createBuffer(&buffer, table.size() * sizeof(int32_t), table.data(), 0, what);
    if (!s.isOk()) return s;
    content = table;
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer);
  return Status::ok();
}

void TableBuffer::release() {
  if (buffer != kNoObject) glDeleteBuffers(1, &buffer);
  buffer = kNoObject;
  content.clear();
}

uint64_t bufferBytes(GLuint buffer) {
  if (buffer == kNoObject) return 0;
  GLint64 bytes = 0;
  glGetNamedBufferParameteri64v(buffer, GL_BUFFER_SIZE, &bytes);
  return bytes > 0 ? uint64_t(bytes) : 0;
}

uint64_t textureBytes(GLuint texture) {
  if (texture == kNoObject) return 0;
  GLint levels = 0;
  glGetTextureParameteriv(texture, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
  uint64_t total = 0;
  for (GLint level = 0; level < std::max(levels, 1); ++level) {
    GLint w = 0, h = 0, d = 0, samples = 0, bits = 0;
    glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_HEIGHT, &h);
    glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_DEPTH, &d);
    glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_SAMPLES, &samples);
    for (GLenum component :
         {GL_TEXTURE_RED_SIZE, GL_TEXTURE_GREEN_SIZE, GL_TEXTURE_BLUE_SIZE, GL_TEXTURE_ALPHA_SIZE,
          GL_TEXTURE_DEPTH_SIZE, GL_TEXTURE_STENCIL_SIZE}) {
      GLint b = 0;
      glGetTextureLevelParameteriv(texture, level, component, &b);
      bits += b;
    }
    total += uint64_t(std::max(w, 0)) * uint64_t(std::max(h, 1)) * uint64_t(std::max(d, 1)) *
             uint64_t(std::max(samples, 1)) * uint64_t(bits) / 8;
  }
  return total;
}

}  // namespace si::detail
