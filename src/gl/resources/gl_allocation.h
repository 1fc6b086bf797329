// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Creating GL storage with a named error instead of a GL error later: every buffer and texture
// of the back-end is made here. Errors pending from before (the application's) are drained
// first so they are not blamed on the allocation.

#include <glad/gl.h>

#include <cstdint>
#include <vector>

#include "gl/programs/program_set.h"
#include "si/core/status.h"

namespace si::detail {

/// Replaces `*buffer` (deleting the old one) by a buffer of `bytes` bytes of immutable storage
/// with `data` (may be null) and `flags`. Fails, leaving `*buffer` kNoObject, with
/// kLimitExceeded naming `what` and the size when the driver reports GL_OUT_OF_MEMORY, and
/// kBackend naming the GL error otherwise.
Status createBuffer(GLuint* buffer, uint64_t bytes, const void* data, GLbitfield flags,
                    const char* what);

/// The bytes of buffer `buffer` as the driver reports them (GL_BUFFER_SIZE); 0 for kNoObject.
uint64_t bufferBytes(GLuint buffer);
/// The bytes of texture `texture`: every level's texels (width x height x depth or layers) at
/// the bits of its components (GL_TEXTURE_*_SIZE), times its samples; 0 for kNoObject.
uint64_t textureBytes(GLuint texture);

/// createBuffer() for an index buffer (immutable, from `data`): on the ES profile it is bound
/// only as indices (gl_profile.h, esMarkIndexBuffer), as WebGL 2 requires.
Status createIndexBuffer(GLuint* buffer, uint64_t bytes, const void* data, const char* what);

/// The same with mutable storage (glNamedBufferData with `usage`), for a stream the driver may
/// orphan on each rewrite.
Status createMutableBuffer(GLuint* buffer, uint64_t bytes, GLenum usage, const char* what);

/// A small table of 32-bit words that the shaders read as a storage buffer (the mask table, the
/// compose table), replaced only when its content changes.
struct TableBuffer {
  GLuint buffer = kNoObject;
  std::vector<int32_t> content;

  /// Makes the buffer hold `table` and binds it at storage binding `binding`. A new buffer
  /// whenever the table changes (another crowd's masks): draws issued before may still read the
  /// old one, which GL keeps until they are done. Rewriting it in place raced with them on the
  /// H100's driver (the second of two crowds' tables read by the first's draws), flushing first
  /// or not. `what` names it in errors (createBuffer's).
  Status upload(const std::vector<int32_t>& table, GLuint binding, const char* what);
  void release();
};

/// Replaces `*texture` by a 2D texture with `levels` levels of `internal_format` storage,
/// `width` x `height`; fails as createBuffer() does (the size named in texels).
Status createTexture2D(GLuint* texture, GLsizei levels, GLenum internal_format, GLsizei width,
                       GLsizei height, const char* what);
/// The same for a multisampled 2D texture of `samples` samples (fixed sample locations).
Status createTexture2DMultisample(GLuint* texture, GLsizei samples, GLenum internal_format,
                                  GLsizei width, GLsizei height, const char* what);
/// The same for a 2D array texture of `layers` layers.
Status createTexture2DArray(GLuint* texture, GLsizei levels, GLenum internal_format,
                            GLsizei width, GLsizei height, GLsizei layers, const char* what);

}  // namespace si::detail
