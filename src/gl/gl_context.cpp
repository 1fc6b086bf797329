// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/gl/gl_context.h"

#include <glad/gl.h>

#include "core/str_cat.h"
#include "gl/host_errors.h"
#include "gl/profile/gl_profile.h"
#include "si/core/log.h"

namespace si {
using detail::strCat;

namespace {
struct Loader {
  GlGetProcAddress get_proc;
  void* user_data;
};
GLADapiproc loadOne(void* user, const char* name) {
  const Loader* l = static_cast<const Loader*>(user);
  return reinterpret_cast<GLADapiproc>(l->get_proc(l->user_data, name));
}
std::string glString(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : "";
}
uint32_t glInt(GLenum name) {
  GLint v = 0;
  glGetIntegerv(name, &v);
  return v > 0 ? static_cast<uint32_t>(v) : 0u;
}
}  // namespace

Status loadGl(GlGetProcAddress get_proc, void* user_data, GlInfo* info) {
  if (get_proc == nullptr || info == nullptr)
    return {StatusCode::kInvalidArgument, "loadGl: get_proc and info must not be null"};
  Loader loader{get_proc, user_data};
  const int version = glad::gladLoadGLUserPtr(&loadOne, &loader);
  if (version == 0)
    return {StatusCode::kBackend, "loadGl: no GL context is current, or glGetString failed"};
  GlInfo out;
  out.major_version = GLAD_VERSION_MAJOR(version);
  out.minor_version = GLAD_VERSION_MINOR(version);
  out.vendor = glString(GL_VENDOR);
  out.renderer = glString(GL_RENDERER);
  out.version = glString(GL_VERSION);
  out.es = out.version.rfind("OpenGL ES ", 0) == 0;
  out.webgl = out.es && out.version.find("WebGL") != std::string::npos;
  detail::setEsProfile(false);
  detail::setWebglProfile(out.webgl);
  if (out.es) {
    if (out.major_version < 3)
      return {StatusCode::kBackend, strCat("loadGl: need OpenGL ES 3.0 or later, the context has '",
                                           out.version, "' (", out.renderer, ")")};
    const Status loaded = detail::loadEsEntryPoints(get_proc, user_data);
    if (!loaded.isOk()) return loaded;
    detail::setEsProfile(true);
  } else if (out.major_version < 4 || (out.major_version == 4 && out.minor_version < 5) ||
             glCreateBuffers == nullptr) {
    return {StatusCode::kBackend, strCat("loadGl: need OpenGL 4.5 core or OpenGL ES 3.0, the ",
                                         "context has '", out.version, "' (", out.renderer, ")")};
  }
  detail::takeHostErrors("loadGl");  // So that the check below blames only the queries.
  out.max_uniform_block_size_bytes = glInt(GL_MAX_UNIFORM_BLOCK_SIZE);
  out.uniform_buffer_offset_alignment = glInt(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT);
  out.max_texture_size = glInt(GL_MAX_TEXTURE_SIZE);
  out.max_renderbuffer_size = glInt(GL_MAX_RENDERBUFFER_SIZE);
  GLint viewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
  out.max_viewport_width = viewport[0] > 0 ? uint32_t(viewport[0]) : 0;
  out.max_viewport_height = viewport[1] > 0 ? uint32_t(viewport[1]) : 0;
  if (!out.es) {  // The ES profile has neither storage buffers nor compute (gl_profile.h).
    GLint64 ssbo = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &ssbo);
    out.max_shader_storage_block_size_bytes = ssbo > 0 ? uint64_t(ssbo) : 0;
    out.storage_buffer_offset_alignment = glInt(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT);
    GLint groups[2] = {0, 0};
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups[0]);
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 1, &groups[1]);
    out.max_compute_groups_x = groups[0] > 0 ? uint32_t(groups[0]) : 0;
    out.max_compute_groups_y = groups[1] > 0 ? uint32_t(groups[1]) : 0;
    out.has_khr_debug = glad::GLAD_GL_KHR_debug != 0;
  }
  Status s = checkGlErrors("loadGl: querying limits");
  if (!s.isOk()) return s;
  *info = std::move(out);
  return Status::ok();
}

const char* glErrorName(uint32_t error) {
  switch (error) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    default: return "GL_UNKNOWN_ERROR";
  }
}

Status checkGlErrors(const char* what) {
  if (glGetError == nullptr)
    return {StatusCode::kBackend, strCat(what, ": GL is not loaded (call loadGl first)")};
  std::string errors;
  // Bounded: a lost context can report errors forever.
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    errors += (errors.empty() ? "" : ", ") + std::string(glErrorName(e));
  }
  if (errors.empty()) return Status::ok();
  return {StatusCode::kBackend, strCat(what, ": ", errors)};
}

namespace detail {

namespace {
// The errors taken from the host on this thread, for takeHostGlErrors().
constexpr size_t kKeptHostErrors = 64;
thread_local std::vector<HostGlError> t_host_errors;
thread_local uint64_t t_dropped_host_errors = 0;
}  // namespace

void takeHostErrors(const char* what) {
  if (glGetError == nullptr) return;
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    logMessage(LogLevel::kWarning, strCat("GL error ", glErrorName(e), " was pending before ", what,
                                          " (left by the application; not the library's): kept for "
                                          "si::takeHostGlErrors"));
    if (t_host_errors.size() < kKeptHostErrors)
      t_host_errors.push_back({uint32_t(e), what});
    else
      ++t_dropped_host_errors;
  }
}

}  // namespace detail

void takeHostGlErrors(std::vector<HostGlError>* out, uint64_t* dropped) {
  if (out != nullptr) out->swap(detail::t_host_errors);
  detail::t_host_errors.clear();
  if (dropped != nullptr) *dropped = detail::t_dropped_host_errors;
  detail::t_dropped_host_errors = 0;
}

}  // namespace si
