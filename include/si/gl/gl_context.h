// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Binding si::gl to a context the application made current (EGL, OSMesa, GLFW, ...): the
/// library never creates a context; it is handed a get-proc-address function.
///
/// Usage:
/// \code
///   // After making a GL 4.5 core (or OpenGL ES 3.0+ / WebGL 2) context current:
///   si::GlInfo info;
///   si::Status s = si::loadGl(&myGetProc, nullptr, &info);
///   // info.max_uniform_block_size_bytes goes to the InstanceBatcher.
/// \endcode

#include <cstdint>
#include <string>
#include <vector>

#include "si/core/status.h"

namespace si {

/// Returns the address of GL function `name` (as eglGetProcAddress, OSMesaGetProcAddress or
/// glfwGetProcAddress do), or null; `user_data` is passed through.
using GlGetProcAddress = void* (*)(void* user_data, const char* name);

/// The context's identity and the limits the library needs, queried once by loadGl().
struct GlInfo {
  std::string vendor;
  std::string renderer;
  std::string version;
  int major_version = 0;
  int minor_version = 0;
  uint32_t max_uniform_block_size_bytes = 0;   ///< GL_MAX_UNIFORM_BLOCK_SIZE.
  uint32_t uniform_buffer_offset_alignment = 0;  ///< GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT.
  uint32_t max_texture_size = 0;               ///< GL_MAX_TEXTURE_SIZE.
  uint32_t max_renderbuffer_size = 0;          ///< GL_MAX_RENDERBUFFER_SIZE.
  /// GL_MAX_VIEWPORT_DIMS: a viewport past them is clamped silently, so offscreen passes
  /// (buildImpostor's capture) refuse targets larger.
  uint32_t max_viewport_width = 0, max_viewport_height = 0;
  /// GL_MAX_SHADER_STORAGE_BLOCK_SIZE: the largest storage buffer a shader may read whole (the
  /// compute ring, the GPU-driven crowd state).
  uint64_t max_shader_storage_block_size_bytes = 0;
  /// GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT (0 on the ES profile).
  uint32_t storage_buffer_offset_alignment = 0;
  /// GL_MAX_COMPUTE_WORK_GROUP_COUNT in x and y (GL guarantees 65535 each): the compute passes
  /// lay their groups out in rows of at most x, at most y rows, and refuse a pass past that
  /// (kLimitExceeded). Lowering them (tests) makes every pass use several rows.
  uint32_t max_compute_groups_x = 0, max_compute_groups_y = 0;
  bool has_khr_debug = false;  ///< Always false on the ES profile (debug output stays the host's).
  /// An OpenGL ES 3.0 or later context (WebGL 2 included): the renderer's ES profile, which
  /// draws the vertex-shader path and refuses what ES 3.0 lacks by name (docs/rendering.md,
  /// "The ES profile"). The storage, compute and debug fields above are then 0.
  bool es = false;
  /// A browser's WebGL 2 context (an ES context whose GL_VERSION names WebGL; Emscripten's):
  /// primitive restart at the fixed index is left alone (always on there), and the state
  /// contract skips the values WebGL answers by a round trip to the GPU process unless
  /// RendererDesc::webgl_restore_raster_state asks for them.
  bool webgl = false;
};

/// Loads the GL 4.5 core entry points through `get_proc` for the context current on this
/// thread and fills `info`. An OpenGL ES context (its GL_VERSION starts "OpenGL ES ") loads the
/// ES profile instead: ES 3.0 entry points, the GL 4.5 direct-state-access calls the profile
/// uses emulated by binding (each puts back the binding it changed). Fails with
/// kInvalidArgument for a null `get_proc` or `info`, and kBackend (naming the version found)
/// when no context is current, it is older than 4.5 core (or ES 3.0), or it lacks an ES 3.0
/// entry point.
/// Entry points are process-wide: load again after switching to a context of another driver.
Status loadGl(GlGetProcAddress get_proc, void* user_data, GlInfo* info);

/// Name of a glGetError() code, e.g. "GL_INVALID_OPERATION", or "GL_UNKNOWN_ERROR".
const char* glErrorName(uint32_t error);

/// Drains glGetError(). Returns kBackend naming `what` and every pending error, or ok when none.
/// Requires loadGl() to have succeeded.
Status checkGlErrors(const char* what);

/// A GL error the application had left pending when a library call had to read glGetError().
struct HostGlError {
  uint32_t error = 0;    ///< The glGetError() code (glErrorName names it).
  std::string taken_by;  ///< The library call (or its step) that took it, e.g. "drawCrowd".
};

/// Gives back the GL errors the library took from the application. GL cannot read an error
/// and leave it pending (glGetError clears it), so a library call that reads errors first takes
/// those already pending, logs each as a warning naming the call (si::setLogCallback), and
/// keeps it for this function. The calls that read errors: every Renderer call with debug
/// checks (RendererDesc::debug_checks); any call that allocates a buffer or texture (init,
/// uploads, a draw that grows its buffers); and those that always check (buildImpostor,
/// captureSkinnedPositions, measureImageLodErrors, readGpuSelection, setCustomTextureArray,
/// MotionTarget). Other calls leave the application's errors pending in GL, so a release draw
/// that allocates nothing reads none. Without debug checks an error a call's own earlier
/// commands raised may be taken the same way (named by the step that took it).
///
/// Moves the errors kept for the calling thread (the thread the context was current on),
/// oldest first, into `*out` (replaced; `out` may be null to forget them) and forgets them. At
/// most 64 are kept; `*dropped`, when non-null, gets how many more were taken since the last
/// call.
void takeHostGlErrors(std::vector<HostGlError>* out, uint64_t* dropped = nullptr);

}  // namespace si
