// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The ES profile's entry points: OpenGL ES 3.0 has no direct state access (GL 4.5's glCreate*,
// glNamed*, glTexture*, glVertexArray*, glProgramUniform*), so each one the ES profile's paths
// call is emulated here by binding the object to a target, calling the ES 3.0 function and
// putting the previous binding back: the host's bindings and the library's state contract
// (gl_state_guard.h) see no difference. Vertex attribute formats and buffer bindings (GL 4.3's
// separate format, ES 3.1) are kept per vertex array and applied with glVertexAttrib(I)Pointer
// once both are known.
#include <glad/gl.h>

#include <cstring>
#include <unordered_map>
#include <unordered_set>

#include "core/str_cat.h"
#include "gl/profile/gl_profile.h"

namespace si::detail {

namespace {

bool g_es = false, g_webgl = false;

// ---- Buffers: edited through GL_COPY_WRITE_BUFFER, which no draw reads. WebGL 2 fixes a
// buffer's kind at its first binding (an index buffer can never be bound elsewhere, nor another
// buffer as indices), so index buffers (esMarkIndexBuffer) are edited through
// GL_ELEMENT_ARRAY_BUFFER of the default vertex array, whose binding is put back too.
std::unordered_set<GLuint>& indexBuffers() {
  static std::unordered_set<GLuint> set;
  return set;
}

class BoundBuffer {
 public:
  explicit BoundBuffer(GLuint buffer) : indices_(indexBuffers().count(buffer) != 0) {
    if (indices_) {
      glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertex_array_);
      glBindVertexArray(0);
      glGetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &previous_);
    } else {
      glGetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &previous_);
    }
    glBindBuffer(target(), buffer);
  }
  ~BoundBuffer() {
    glBindBuffer(target(), GLuint(previous_));
    if (indices_) glBindVertexArray(GLuint(vertex_array_));
  }
  BoundBuffer(const BoundBuffer&) = delete;
  BoundBuffer& operator=(const BoundBuffer&) = delete;
  GLenum target() const { return indices_ ? GL_ELEMENT_ARRAY_BUFFER : GL_COPY_WRITE_BUFFER; }

 private:
  bool indices_;
  GLint previous_ = 0, vertex_array_ = 0;
};

// Names only: the first binding (an upload, or the draw's) creates the buffer with its kind.
void GLAD_API_PTR createBuffers(GLsizei n, GLuint* buffers) {
  glGenBuffers(n, buffers);
}
PFNGLDELETEBUFFERSPROC g_delete_buffers = nullptr;
void GLAD_API_PTR deleteBuffers(GLsizei n, const GLuint* buffers) {
  for (GLsizei i = 0; i < n; ++i) indexBuffers().erase(buffers[i]);
  g_delete_buffers(n, buffers);
}
void GLAD_API_PTR namedBufferStorage(GLuint buffer, GLsizeiptr size, const void* data,
                                     GLbitfield flags) {
  BoundBuffer b(buffer);
  glBufferData(b.target(), size, data,
               (flags & GL_DYNAMIC_STORAGE_BIT) != 0 ? GL_DYNAMIC_DRAW : GL_STATIC_DRAW);
}
void GLAD_API_PTR namedBufferData(GLuint buffer, GLsizeiptr size, const void* data, GLenum usage) {
  BoundBuffer b(buffer);
  glBufferData(b.target(), size, data, usage);
}
void GLAD_API_PTR namedBufferSubData(GLuint buffer, GLintptr offset, GLsizeiptr size,
                                     const void* data) {
  BoundBuffer b(buffer);
  glBufferSubData(b.target(), offset, size, data);
}
// ES 3.0 has no glGetBufferSubData: a read mapping of the range.
void GLAD_API_PTR getNamedBufferSubData(GLuint buffer, GLintptr offset, GLsizeiptr size,
                                        void* data) {
  BoundBuffer b(buffer);
  const void* p = glMapBufferRange(b.target(), offset, size, GL_MAP_READ_BIT);
  if (p != nullptr) std::memcpy(data, p, size_t(size));
  glUnmapBuffer(b.target());
}

// ---- Textures: ES has no query of a texture's target, so the emulation keeps the target of
// every texture it created (a host texture handed to the library is taken as a 2D array:
// Renderer::setCustomTextureArray, the only one).
struct TextureInfo {
  GLenum target = GL_TEXTURE_2D_ARRAY;
  GLint depth = 0;  // Layers of a 2D array (glTextureStorage3D).
};
std::unordered_map<GLuint, TextureInfo>& textures() {
  static std::unordered_map<GLuint, TextureInfo> map;
  return map;
}
PFNGLDELETETEXTURESPROC g_delete_textures = nullptr;
PFNGLDELETEVERTEXARRAYSPROC g_delete_vertex_arrays = nullptr;

GLenum bindingQuery(GLenum target) {
  switch (target) {
    case GL_TEXTURE_2D:
      return GL_TEXTURE_BINDING_2D;
    case GL_TEXTURE_3D:
      return GL_TEXTURE_BINDING_3D;
    case GL_TEXTURE_CUBE_MAP:
      return GL_TEXTURE_BINDING_CUBE_MAP;
    default:
      return GL_TEXTURE_BINDING_2D_ARRAY;
  }
}
GLenum targetOf(GLuint texture) {
  const auto it = textures().find(texture);
  return it == textures().end() ? GLenum(GL_TEXTURE_2D_ARRAY) : it->second.target;
}

// Binds `texture` on the active unit for the scope, then puts that unit's binding back.
class BoundTexture {
 public:
  explicit BoundTexture(GLuint texture) : target_(targetOf(texture)) {
    glGetIntegerv(bindingQuery(target_), &previous_);
    glBindTexture(target_, texture);
  }
  ~BoundTexture() { glBindTexture(target_, GLuint(previous_)); }
  BoundTexture(const BoundTexture&) = delete;
  BoundTexture& operator=(const BoundTexture&) = delete;
  GLenum target() const { return target_; }

 private:
  GLenum target_;
  GLint previous_ = 0;
};

void GLAD_API_PTR createTextures(GLenum target, GLsizei n, GLuint* ids) {
  glGenTextures(n, ids);
  for (GLsizei i = 0; i < n; ++i) {
    textures()[ids[i]] = TextureInfo{target, 0};
    BoundTexture create(ids[i]);
  }
}
void GLAD_API_PTR deleteTextures(GLsizei n, const GLuint* ids) {
  for (GLsizei i = 0; i < n; ++i) textures().erase(ids[i]);
  g_delete_textures(n, ids);
}
void GLAD_API_PTR textureStorage2D(GLuint texture, GLsizei levels, GLenum format, GLsizei w,
                                   GLsizei h) {
  BoundTexture t(texture);
  glTexStorage2D(t.target(), levels, format, w, h);
}
void GLAD_API_PTR textureStorage3D(GLuint texture, GLsizei levels, GLenum format, GLsizei w,
                                   GLsizei h, GLsizei d) {
  BoundTexture t(texture);
  glTexStorage3D(t.target(), levels, format, w, h, d);
  textures()[texture].depth = d;
}
void GLAD_API_PTR textureSubImage2D(GLuint texture, GLint level, GLint x, GLint y, GLsizei w,
                                    GLsizei h, GLenum format, GLenum type, const void* pixels) {
  BoundTexture t(texture);
  glTexSubImage2D(t.target(), level, x, y, w, h, format, type, pixels);
}
void GLAD_API_PTR textureSubImage3D(GLuint texture, GLint level, GLint x, GLint y, GLint z,
                                    GLsizei w, GLsizei h, GLsizei d, GLenum format, GLenum type,
                                    const void* pixels) {
  BoundTexture t(texture);
  glTexSubImage3D(t.target(), level, x, y, z, w, h, d, format, type, pixels);
}
void GLAD_API_PTR textureParameteri(GLuint texture, GLenum name, GLint value) {
  BoundTexture t(texture);
  glTexParameteri(t.target(), name, value);
}
void GLAD_API_PTR generateTextureMipmap(GLuint texture) {
  BoundTexture t(texture);
  glGenerateMipmap(t.target());
}
void GLAD_API_PTR getTextureParameteriv(GLuint texture, GLenum name, GLint* out) {
  if (name == GL_TEXTURE_TARGET) {
    *out = GLint(targetOf(texture));
    return;
  }
  BoundTexture t(texture);
  glGetTexParameteriv(t.target(), name, out);
}
// Layers of a 2D array: recorded at glTextureStorage3D; a host's texture through ES 3.1's
// glGetTexLevelParameteriv where the context has it, else 0 (unknown).
PFNGLGETTEXLEVELPARAMETERIVPROC g_level_parameter = nullptr;
void GLAD_API_PTR getTextureLevelParameteriv(GLuint texture, GLint level, GLenum name, GLint* out) {
  *out = 0;
  const auto it = textures().find(texture);
  if (name == GL_TEXTURE_DEPTH && level == 0 && it != textures().end() && it->second.depth > 0) {
    *out = it->second.depth;
    return;
  }
  if (g_level_parameter == nullptr) return;
  BoundTexture t(texture);
  g_level_parameter(t.target(), level, name, out);
}
// Binds to `unit` without changing the active unit.
void GLAD_API_PTR bindTextureUnit(GLuint unit, GLuint texture) {
  GLint active = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  glActiveTexture(GLenum(GL_TEXTURE0 + unit));
  glBindTexture(targetOf(texture), texture);
  glActiveTexture(GLenum(active));
}

// ---- Vertex arrays: each one's attribute formats and buffer bindings (GL 4.3's separate
// format), applied as ES 3.0 glVertexAttrib(I)Pointer calls whenever both are known.
struct Attribute {
  bool formatted = false, integer = false;
  GLint size = 4;
  GLenum type = GL_FLOAT;
  GLboolean normalized = GL_FALSE;
  GLuint relative_offset = 0, binding = 0;
};
struct Binding {
  GLuint buffer = 0;
  GLintptr offset = 0;
  GLsizei stride = 0;
  GLuint divisor = 0;
};
constexpr GLuint kMaxAttributes = 16;
struct VertexArray {
  Attribute attributes[kMaxAttributes];
  Binding bindings[kMaxAttributes];
};
std::unordered_map<GLuint, VertexArray>& vertexArrays() {
  static std::unordered_map<GLuint, VertexArray> map;
  return map;
}

class BoundVertexArray {
 public:
  explicit BoundVertexArray(GLuint vao) {
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &previous_);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer_);  // Not vertex array state.
    glBindVertexArray(vao);
  }
  ~BoundVertexArray() {
    glBindVertexArray(GLuint(previous_));
    glBindBuffer(GL_ARRAY_BUFFER, GLuint(array_buffer_));
  }
  BoundVertexArray(const BoundVertexArray&) = delete;
  BoundVertexArray& operator=(const BoundVertexArray&) = delete;

 private:
  GLint previous_ = 0, array_buffer_ = 0;
};

// Re-specifies every formatted attribute reading binding `binding` (all of them for ~0u).
void applyAttributes(GLuint vao, GLuint binding) {
  const VertexArray& v = vertexArrays()[vao];
  BoundVertexArray bound(vao);
  for (GLuint a = 0; a < kMaxAttributes; ++a) {
    const Attribute& at = v.attributes[a];
    if (!at.formatted || at.binding >= kMaxAttributes) continue;
    if (binding != ~0u && at.binding != binding) continue;
    const Binding& b = v.bindings[at.binding];
    if (b.buffer == 0) continue;
    glBindBuffer(GL_ARRAY_BUFFER, b.buffer);
    const void* pointer = reinterpret_cast<const void*>(uintptr_t(b.offset) + at.relative_offset);
    if (at.integer)
      glVertexAttribIPointer(a, at.size, at.type, b.stride, pointer);
    else
      glVertexAttribPointer(a, at.size, at.type, at.normalized, b.stride, pointer);
    glVertexAttribDivisor(a, b.divisor);
  }
}

void GLAD_API_PTR createVertexArrays(GLsizei n, GLuint* ids) {
  glGenVertexArrays(n, ids);
  for (GLsizei i = 0; i < n; ++i) {
    vertexArrays()[ids[i]] = VertexArray{};
    BoundVertexArray create(ids[i]);
  }
}
void GLAD_API_PTR deleteVertexArrays(GLsizei n, const GLuint* ids) {
  for (GLsizei i = 0; i < n; ++i) vertexArrays().erase(ids[i]);
  g_delete_vertex_arrays(n, ids);
}
void GLAD_API_PTR vertexArrayVertexBuffer(GLuint vao, GLuint binding, GLuint buffer,
                                          GLintptr offset, GLsizei stride) {
  if (binding >= kMaxAttributes) return;
  Binding& b = vertexArrays()[vao].bindings[binding];
  b.buffer = buffer;
  b.offset = offset;
  b.stride = stride;
  applyAttributes(vao, binding);
}
void GLAD_API_PTR vertexArrayBindingDivisor(GLuint vao, GLuint binding, GLuint divisor) {
  if (binding >= kMaxAttributes) return;
  vertexArrays()[vao].bindings[binding].divisor = divisor;
  applyAttributes(vao, binding);
}
void GLAD_API_PTR vertexArrayElementBuffer(GLuint vao, GLuint buffer) {
  BoundVertexArray bound(vao);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffer);  // Vertex array state.
}
void GLAD_API_PTR enableVertexArrayAttrib(GLuint vao, GLuint index) {
  BoundVertexArray bound(vao);
  glEnableVertexAttribArray(index);
}
void setFormat(GLuint vao, GLuint index, const Attribute& format) {
  if (index >= kMaxAttributes) return;
  Attribute& a = vertexArrays()[vao].attributes[index];
  const GLuint binding = a.binding;
  a = format;
  a.binding = binding;
  applyAttributes(vao, binding);
}
void GLAD_API_PTR vertexArrayAttribFormat(GLuint vao, GLuint index, GLint size, GLenum type,
                                          GLboolean normalized, GLuint offset) {
  setFormat(vao, index, Attribute{true, false, size, type, normalized, offset, 0});
}
void GLAD_API_PTR vertexArrayAttribIFormat(GLuint vao, GLuint index, GLint size, GLenum type,
                                           GLuint offset) {
  setFormat(vao, index, Attribute{true, true, size, type, GL_FALSE, offset, 0});
}
void GLAD_API_PTR vertexArrayAttribBinding(GLuint vao, GLuint index, GLuint binding) {
  if (index >= kMaxAttributes) return;
  vertexArrays()[vao].attributes[index].binding = binding;
  applyAttributes(vao, binding);
}

// ---- Program uniforms: set on the program made current for the call.
template <typename Set>
void onProgram(GLuint program, const Set& set) {
  GLint previous = 0;
  glGetIntegerv(GL_CURRENT_PROGRAM, &previous);
  if (GLuint(previous) != program) glUseProgram(program);
  set();
  if (GLuint(previous) != program) glUseProgram(GLuint(previous));
}
void GLAD_API_PTR programUniform1i(GLuint p, GLint l, GLint v) {
  onProgram(p, [&] { glUniform1i(l, v); });
}
void GLAD_API_PTR programUniform1ui(GLuint p, GLint l, GLuint v) {
  onProgram(p, [&] { glUniform1ui(l, v); });
}
void GLAD_API_PTR programUniform3fv(GLuint p, GLint l, GLsizei n, const GLfloat* v) {
  onProgram(p, [&] { glUniform3fv(l, n, v); });
}
void GLAD_API_PTR programUniform4fv(GLuint p, GLint l, GLsizei n, const GLfloat* v) {
  onProgram(p, [&] { glUniform4fv(l, n, v); });
}
void GLAD_API_PTR programUniformMatrix4fv(GLuint p, GLint l, GLsizei n, GLboolean t,
                                          const GLfloat* v) {
  onProgram(p, [&] { glUniformMatrix4fv(l, n, t, v); });
}

// ---- Framebuffers: Renderer::clear's clears of the bound draw framebuffer.
void GLAD_API_PTR clearNamedFramebufferfv(GLuint framebuffer, GLenum buffer, GLint draw_buffer,
                                          const GLfloat* value) {
  GLint previous = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous);
  if (GLuint(previous) != framebuffer) glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
  glClearBufferfv(buffer, draw_buffer, value);
  if (GLuint(previous) != framebuffer) glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(previous));
}

template <typename Pointer>
bool load(GlGetProcAddress get_proc, void* user_data, const char* name, Pointer* out) {
  *out = reinterpret_cast<Pointer>(get_proc(user_data, name));
  return *out != nullptr;
}

}  // namespace

bool webglProfile() {
  return g_webgl;
}
void setWebglProfile(bool webgl) {
  g_webgl = webgl;
}

void esMarkIndexBuffer(unsigned buffer) {
  if (g_es) indexBuffers().insert(buffer);
}

bool esProfile() {
  return g_es;
}
void setEsProfile(bool es) {
  g_es = es;
}

Status loadEsEntryPoints(GlGetProcAddress get_proc, void* user_data) {
  // ES 3.0 functions that came to desktop GL after 3.0: glad loads a version string's "3.x"
  // functions only (WebGL 2 reads "OpenGL ES 3.0"), so these are loaded by name. A context
  // without one of them is no ES 3.0 context.
  const char* missing = nullptr;
#define SI_ES_LOAD(name) \
  if (!load(get_proc, user_data, #name, &name) && missing == nullptr) missing = #name
  SI_ES_LOAD(glGetUniformBlockIndex);
  SI_ES_LOAD(glUniformBlockBinding);
  SI_ES_LOAD(glGetActiveUniformBlockiv);
  SI_ES_LOAD(glDrawArraysInstanced);
  SI_ES_LOAD(glDrawElementsInstanced);
  SI_ES_LOAD(glCopyBufferSubData);
  SI_ES_LOAD(glFenceSync);
  SI_ES_LOAD(glDeleteSync);
  SI_ES_LOAD(glClientWaitSync);
  SI_ES_LOAD(glGetInteger64v);
  SI_ES_LOAD(glGetInteger64i_v);
  SI_ES_LOAD(glVertexAttribDivisor);
  SI_ES_LOAD(glBindSampler);
  SI_ES_LOAD(glTexStorage2D);
  SI_ES_LOAD(glTexStorage3D);
#undef SI_ES_LOAD
  if (!load(get_proc, user_data, "glDeleteBuffers", &g_delete_buffers) && missing == nullptr)
    missing = "glDeleteBuffers";
  if (!load(get_proc, user_data, "glDeleteTextures", &g_delete_textures) && missing == nullptr)
    missing = "glDeleteTextures";
  if (!load(get_proc, user_data, "glDeleteVertexArrays", &g_delete_vertex_arrays) &&
      missing == nullptr)
    missing = "glDeleteVertexArrays";
  if (missing != nullptr)
    return {StatusCode::kBackend, strCat("loadGl: the OpenGL ES context has no ", missing)};
  load(get_proc, user_data, "glGetTexLevelParameteriv", &g_level_parameter);         // ES 3.1.
  load(get_proc, user_data, "glGetGraphicsResetStatus", &glGetGraphicsResetStatus);  // ES 3.2.
  glCreateBuffers = &createBuffers;
  glDeleteBuffers = &deleteBuffers;
  glNamedBufferStorage = &namedBufferStorage;
  glNamedBufferData = &namedBufferData;
  glNamedBufferSubData = &namedBufferSubData;
  glGetNamedBufferSubData = &getNamedBufferSubData;
  glCreateTextures = &createTextures;
  glDeleteTextures = &deleteTextures;
  glTextureStorage2D = &textureStorage2D;
  glTextureStorage3D = &textureStorage3D;
  glTextureSubImage2D = &textureSubImage2D;
  glTextureSubImage3D = &textureSubImage3D;
  glTextureParameteri = &textureParameteri;
  glGenerateTextureMipmap = &generateTextureMipmap;
  glGetTextureParameteriv = &getTextureParameteriv;
  glGetTextureLevelParameteriv = &getTextureLevelParameteriv;
  glBindTextureUnit = &bindTextureUnit;
  glCreateVertexArrays = &createVertexArrays;
  glDeleteVertexArrays = &deleteVertexArrays;
  glVertexArrayVertexBuffer = &vertexArrayVertexBuffer;
  glVertexArrayBindingDivisor = &vertexArrayBindingDivisor;
  glVertexArrayElementBuffer = &vertexArrayElementBuffer;
  glEnableVertexArrayAttrib = &enableVertexArrayAttrib;
  glVertexArrayAttribFormat = &vertexArrayAttribFormat;
  glVertexArrayAttribIFormat = &vertexArrayAttribIFormat;
  glVertexArrayAttribBinding = &vertexArrayAttribBinding;
  glProgramUniform1i = &programUniform1i;
  glProgramUniform1ui = &programUniform1ui;
  glProgramUniform3fv = &programUniform3fv;
  glProgramUniform4fv = &programUniform4fv;
  glProgramUniformMatrix4fv = &programUniformMatrix4fv;
  glClearNamedFramebufferfv = &clearNamedFramebufferfv;
  return Status::ok();
}

}  // namespace si::detail
