// See host_state.h.
#include "host_state.h"

#include <glad/gl.h>

#include <algorithm>
#include <cstring>

namespace host {

namespace {

constexpr GLenum kTargets[5] = {GL_TEXTURE_2D, GL_TEXTURE_2D_ARRAY, GL_TEXTURE_3D,
                                GL_TEXTURE_CUBE_MAP, GL_TEXTURE_RECTANGLE};
constexpr GLenum kTargetBindings[5] = {GL_TEXTURE_BINDING_2D, GL_TEXTURE_BINDING_2D_ARRAY,
                                       GL_TEXTURE_BINDING_3D, GL_TEXTURE_BINDING_CUBE_MAP,
                                       GL_TEXTURE_BINDING_RECTANGLE};
constexpr int kUnits = 8, kImages = 4, kUniformBindings = 16, kFeedbackBindings = 4;

// Enables the snapshot covers, with the value the engine gives each (the opposite of what the
// library's draws need where they need one: depth test, culling, no discard, no restart).
struct Cap {
  const char* name;
  GLenum cap;
  bool host_value;
};
constexpr Cap kCaps[] = {
    {"GL_DEPTH_TEST", GL_DEPTH_TEST, false},
    {"GL_CULL_FACE", GL_CULL_FACE, false},
    {"GL_BLEND", GL_BLEND, true},
    {"GL_SCISSOR_TEST", GL_SCISSOR_TEST, true},
    {"GL_STENCIL_TEST", GL_STENCIL_TEST, true},
    {"GL_RASTERIZER_DISCARD", GL_RASTERIZER_DISCARD, true},
    {"GL_POLYGON_OFFSET_FILL", GL_POLYGON_OFFSET_FILL, true},
    {"GL_PRIMITIVE_RESTART", GL_PRIMITIVE_RESTART, true},
    {"GL_PRIMITIVE_RESTART_FIXED_INDEX", GL_PRIMITIVE_RESTART_FIXED_INDEX, true},
    {"GL_PROGRAM_POINT_SIZE", GL_PROGRAM_POINT_SIZE, true},
    {"GL_DEPTH_CLAMP", GL_DEPTH_CLAMP, true},
    {"GL_MULTISAMPLE", GL_MULTISAMPLE, false},
    {"GL_DITHER", GL_DITHER, false},
    {"GL_FRAMEBUFFER_SRGB", GL_FRAMEBUFFER_SRGB, true},
    {"GL_SAMPLE_ALPHA_TO_COVERAGE", GL_SAMPLE_ALPHA_TO_COVERAGE, true},
    {"GL_DEBUG_OUTPUT", GL_DEBUG_OUTPUT, true},
    {"GL_DEBUG_OUTPUT_SYNCHRONOUS", GL_DEBUG_OUTPUT_SYNCHRONOUS, true},
};

// Integer state (glGetIntegerv; `count` values).
struct Value {
  const char* name;
  GLenum pname;
  int count;
};
constexpr Value kValues[] = {
    {"GL_CURRENT_PROGRAM", GL_CURRENT_PROGRAM, 1},
    {"GL_VERTEX_ARRAY_BINDING", GL_VERTEX_ARRAY_BINDING, 1},
    {"GL_ARRAY_BUFFER_BINDING", GL_ARRAY_BUFFER_BINDING, 1},
    {"GL_ELEMENT_ARRAY_BUFFER_BINDING", GL_ELEMENT_ARRAY_BUFFER_BINDING, 1},
    {"GL_UNIFORM_BUFFER_BINDING", GL_UNIFORM_BUFFER_BINDING, 1},
    {"GL_SHADER_STORAGE_BUFFER_BINDING", GL_SHADER_STORAGE_BUFFER_BINDING, 1},
    {"GL_DRAW_INDIRECT_BUFFER_BINDING", GL_DRAW_INDIRECT_BUFFER_BINDING, 1},
    {"GL_DISPATCH_INDIRECT_BUFFER_BINDING", GL_DISPATCH_INDIRECT_BUFFER_BINDING, 1},
    {"GL_PIXEL_PACK_BUFFER_BINDING", GL_PIXEL_PACK_BUFFER_BINDING, 1},
    {"GL_PIXEL_UNPACK_BUFFER_BINDING", GL_PIXEL_UNPACK_BUFFER_BINDING, 1},
    {"GL_COPY_READ_BUFFER_BINDING", GL_COPY_READ_BUFFER_BINDING, 1},
    {"GL_COPY_WRITE_BUFFER_BINDING", GL_COPY_WRITE_BUFFER_BINDING, 1},
    {"GL_TRANSFORM_FEEDBACK_BUFFER_BINDING", GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, 1},
    {"GL_QUERY_BUFFER_BINDING", GL_QUERY_BUFFER_BINDING, 1},
    {"GL_ATOMIC_COUNTER_BUFFER_BINDING", GL_ATOMIC_COUNTER_BUFFER_BINDING, 1},
    {"GL_TEXTURE_BUFFER_BINDING", GL_TEXTURE_BUFFER_BINDING, 1},
    {"GL_TRANSFORM_FEEDBACK_BINDING", GL_TRANSFORM_FEEDBACK_BINDING, 1},
    {"GL_DRAW_FRAMEBUFFER_BINDING", GL_DRAW_FRAMEBUFFER_BINDING, 1},
    {"GL_READ_FRAMEBUFFER_BINDING", GL_READ_FRAMEBUFFER_BINDING, 1},
    {"GL_RENDERBUFFER_BINDING", GL_RENDERBUFFER_BINDING, 1},
    {"GL_ACTIVE_TEXTURE", GL_ACTIVE_TEXTURE, 1},
    {"GL_DEPTH_FUNC", GL_DEPTH_FUNC, 1},
    {"GL_DEPTH_WRITEMASK", GL_DEPTH_WRITEMASK, 1},
    {"GL_COLOR_WRITEMASK", GL_COLOR_WRITEMASK, 4},
    {"GL_CULL_FACE_MODE", GL_CULL_FACE_MODE, 1},
    {"GL_FRONT_FACE", GL_FRONT_FACE, 1},
    {"GL_POLYGON_MODE", GL_POLYGON_MODE, 1},
    {"GL_BLEND_SRC_RGB", GL_BLEND_SRC_RGB, 1},
    {"GL_BLEND_DST_RGB", GL_BLEND_DST_RGB, 1},
    {"GL_BLEND_EQUATION_RGB", GL_BLEND_EQUATION_RGB, 1},
    {"GL_STENCIL_FUNC", GL_STENCIL_FUNC, 1},
    {"GL_STENCIL_REF", GL_STENCIL_REF, 1},
    {"GL_STENCIL_WRITEMASK", GL_STENCIL_WRITEMASK, 1},
    {"GL_VIEWPORT", GL_VIEWPORT, 4},
    {"GL_SCISSOR_BOX", GL_SCISSOR_BOX, 4},
    {"GL_STENCIL_CLEAR_VALUE", GL_STENCIL_CLEAR_VALUE, 1},
    {"GL_PRIMITIVE_RESTART_INDEX", GL_PRIMITIVE_RESTART_INDEX, 1},
    {"GL_PROVOKING_VERTEX", GL_PROVOKING_VERTEX, 1},
    {"GL_PATCH_VERTICES", GL_PATCH_VERTICES, 1},
    {"GL_CLIP_ORIGIN", GL_CLIP_ORIGIN, 1},
    {"GL_CLIP_DEPTH_MODE", GL_CLIP_DEPTH_MODE, 1},
    {"GL_UNPACK_SWAP_BYTES", GL_UNPACK_SWAP_BYTES, 1},
    {"GL_UNPACK_LSB_FIRST", GL_UNPACK_LSB_FIRST, 1},
    {"GL_UNPACK_ROW_LENGTH", GL_UNPACK_ROW_LENGTH, 1},
    {"GL_UNPACK_IMAGE_HEIGHT", GL_UNPACK_IMAGE_HEIGHT, 1},
    {"GL_UNPACK_SKIP_ROWS", GL_UNPACK_SKIP_ROWS, 1},
    {"GL_UNPACK_SKIP_PIXELS", GL_UNPACK_SKIP_PIXELS, 1},
    {"GL_UNPACK_SKIP_IMAGES", GL_UNPACK_SKIP_IMAGES, 1},
    {"GL_UNPACK_ALIGNMENT", GL_UNPACK_ALIGNMENT, 1},
    {"GL_PACK_SWAP_BYTES", GL_PACK_SWAP_BYTES, 1},
    {"GL_PACK_LSB_FIRST", GL_PACK_LSB_FIRST, 1},
    {"GL_PACK_ROW_LENGTH", GL_PACK_ROW_LENGTH, 1},
    {"GL_PACK_IMAGE_HEIGHT", GL_PACK_IMAGE_HEIGHT, 1},
    {"GL_PACK_SKIP_ROWS", GL_PACK_SKIP_ROWS, 1},
    {"GL_PACK_SKIP_PIXELS", GL_PACK_SKIP_PIXELS, 1},
    {"GL_PACK_SKIP_IMAGES", GL_PACK_SKIP_IMAGES, 1},
    {"GL_PACK_ALIGNMENT", GL_PACK_ALIGNMENT, 1},
};
// Float state, compared by its bits.
constexpr Value kFloats[] = {
    {"GL_COLOR_CLEAR_VALUE", GL_COLOR_CLEAR_VALUE, 4},
    {"GL_DEPTH_CLEAR_VALUE", GL_DEPTH_CLEAR_VALUE, 1},
    {"GL_DEPTH_RANGE", GL_DEPTH_RANGE, 2},
    {"GL_POLYGON_OFFSET_FACTOR", GL_POLYGON_OFFSET_FACTOR, 1},
    {"GL_POINT_SIZE", GL_POINT_SIZE, 1},
};

void add(GlSnapshot* s, std::string name, int64_t value) {
  s->values.emplace_back(std::move(name), value);
}

GLint limit(GLenum pname, GLint cap) {
  GLint v = 0;
  glGetIntegerv(pname, &v);
  return std::min(v, cap);
}

void indexed(GlSnapshot* s, const char* name, GLenum binding, GLenum start, GLenum size,
             GLint count) {
  for (GLint i = 0; i < count; ++i) {
    GLint buffer = 0;
    GLint64 offset = 0, bytes = 0;
    glGetIntegeri_v(binding, GLuint(i), &buffer);
    glGetInteger64i_v(start, GLuint(i), &offset);
    glGetInteger64i_v(size, GLuint(i), &bytes);
    const std::string n = std::string(name) + "[" + std::to_string(i) + "]";
    add(s, n, buffer);
    add(s, n + ".start", offset);
    add(s, n + ".size", bytes);
  }
}

}  // namespace

GlSnapshot snapshot(std::vector<std::string>* errors) {
  GlSnapshot s;
  for (const Cap& c : kCaps) add(&s, c.name, glIsEnabled(c.cap));
  for (const Value& v : kValues) {
    GLint values[4] = {};
    glGetIntegerv(v.pname, values);
    for (int k = 0; k < v.count; ++k)
      add(&s, v.count == 1 ? v.name : std::string(v.name) + "[" + std::to_string(k) + "]",
          values[k]);
  }
  for (const Value& v : kFloats) {
    GLfloat values[4] = {};
    glGetFloatv(v.pname, values);
    for (int k = 0; k < v.count; ++k) {
      int32_t bits = 0;
      std::memcpy(&bits, &values[k], 4);
      add(&s, v.count == 1 ? v.name : std::string(v.name) + "[" + std::to_string(k) + "]", bits);
    }
  }
  indexed(&s, "GL_UNIFORM_BUFFER_BINDING", GL_UNIFORM_BUFFER_BINDING, GL_UNIFORM_BUFFER_START,
          GL_UNIFORM_BUFFER_SIZE, limit(GL_MAX_UNIFORM_BUFFER_BINDINGS, kUniformBindings));
  indexed(&s, "GL_SHADER_STORAGE_BUFFER_BINDING", GL_SHADER_STORAGE_BUFFER_BINDING,
          GL_SHADER_STORAGE_BUFFER_START, GL_SHADER_STORAGE_BUFFER_SIZE,
          limit(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, 32));
  indexed(&s, "GL_TRANSFORM_FEEDBACK_BUFFER_BINDING", GL_TRANSFORM_FEEDBACK_BUFFER_BINDING,
          GL_TRANSFORM_FEEDBACK_BUFFER_START, GL_TRANSFORM_FEEDBACK_BUFFER_SIZE,
          kFeedbackBindings);
  GLint active = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  for (int u = 0; u < kUnits; ++u) {
    glActiveTexture(GLenum(GL_TEXTURE0 + u));
    const std::string unit = "unit " + std::to_string(u) + " ";
    for (int t = 0; t < 5; ++t) {
      GLint texture = 0;
      glGetIntegerv(kTargetBindings[t], &texture);
      add(&s, unit + "texture target " + std::to_string(kTargets[t]), texture);
    }
    GLint sampler = 0;
    glGetIntegerv(GL_SAMPLER_BINDING, &sampler);
    add(&s, unit + "GL_SAMPLER_BINDING", sampler);
  }
  glActiveTexture(GLenum(active));
  for (int i = 0; i < kImages; ++i) {
    const std::string image = "image unit " + std::to_string(i) + " ";
    GLint v = 0;
    for (const auto& [name, pname] : {std::pair<const char*, GLenum>{"name", GL_IMAGE_BINDING_NAME},
                                      {"level", GL_IMAGE_BINDING_LEVEL},
                                      {"layer", GL_IMAGE_BINDING_LAYER},
                                      {"access", GL_IMAGE_BINDING_ACCESS},
                                      {"format", GL_IMAGE_BINDING_FORMAT}}) {
      glGetIntegeri_v(pname, GLuint(i), &v);
      add(&s, image + name, v);
    }
    GLboolean layered = GL_FALSE;
    glGetBooleani_v(GL_IMAGE_BINDING_LAYERED, GLuint(i), &layered);
    add(&s, image + "layered", layered);
  }
  void* callback = nullptr;
  void* user = nullptr;
  glGetPointerv(GL_DEBUG_CALLBACK_FUNCTION, &callback);
  glGetPointerv(GL_DEBUG_CALLBACK_USER_PARAM, &user);
  add(&s, "GL_DEBUG_CALLBACK_FUNCTION", int64_t(reinterpret_cast<intptr_t>(callback)));
  add(&s, "GL_DEBUG_CALLBACK_USER_PARAM", int64_t(reinterpret_cast<intptr_t>(user)));
  GLint query = 0;
  glGetQueryiv(GL_TIME_ELAPSED, GL_CURRENT_QUERY, &query);
  add(&s, "GL_TIME_ELAPSED GL_CURRENT_QUERY", query);
  for (GLenum e = glGetError(); e != GL_NO_ERROR && errors != nullptr; e = glGetError())
    errors->push_back("snapshot: GL error " + std::to_string(e));
  return s;
}

std::string differences(const GlSnapshot& before, const GlSnapshot& after,
                        const std::string& ignore_prefix) {
  std::string out;
  if (before.values.size() != after.values.size()) return "the snapshots differ in size";
  for (size_t k = 0; k < before.values.size(); ++k) {
    const auto& [name, a] = before.values[k];
    const int64_t b = after.values[k].second;
    if (a == b || (!ignore_prefix.empty() && name.rfind(ignore_prefix, 0) == 0)) continue;
    out += (out.empty() ? "" : ", ") + name + " " + std::to_string(a) + " -> " + std::to_string(b);
  }
  return out;
}

std::string HostState::create(uint32_t width, uint32_t height) {
  width_ = width;
  height_ = height;
  glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &uniform_alignment_);
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &storage_alignment_);
  // A program of the engine's own.
  const char* vs = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
  const char* fs = "#version 450 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n";
  program_ = glCreateProgram();
  for (const auto& [type, text] : {std::pair<GLenum, const char*>{GL_VERTEX_SHADER, vs},
                                   {GL_FRAGMENT_SHADER, fs}}) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    glAttachShader(program_, shader);
    glDeleteShader(shader);
  }
  glLinkProgram(program_);
  GLint linked = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &linked);
  if (!linked) return "the engine's program did not link";
  glCreateVertexArrays(1, &vertex_array_);
  glCreateBuffers(64, buffers_);
  for (GLuint b : buffers_) glNamedBufferStorage(b, 4096, nullptr, GL_DYNAMIC_STORAGE_BIT);
  glVertexArrayElementBuffer(vertex_array_, buffers_[1]);
  for (int u = 0; u < kUnits; ++u)
    for (int t = 0; t < 5; ++t) {
      GLuint& tex = textures_[u][t];
      glCreateTextures(kTargets[t], 1, &tex);
      if (kTargets[t] == GL_TEXTURE_2D_ARRAY || kTargets[t] == GL_TEXTURE_3D)
        glTextureStorage3D(tex, 1, GL_RGBA8, 4, 4, 2);
      else
        glTextureStorage2D(tex, 1, GL_RGBA8, 4, 4);
    }
  glCreateSamplers(kUnits, samplers_);
  glCreateTextures(GL_TEXTURE_2D, kImages, images_);
  for (GLuint t : images_) glTextureStorage2D(t, 2, GL_R32F, 4, 4);
  glCreateTransformFeedbacks(1, &feedback_);
  glCreateRenderbuffers(1, &renderbuffer_);
  glNamedRenderbufferStorage(renderbuffer_, GL_RGBA8, GLsizei(width), GLsizei(height));
  glCreateTextures(GL_TEXTURE_2D, 3, attachments_);
  glTextureStorage2D(attachments_[0], 1, GL_RGBA8, GLsizei(width), GLsizei(height));
  glTextureStorage2D(attachments_[1], 1, GL_RG16F, GLsizei(width), GLsizei(height));
  glTextureStorage2D(attachments_[2], 1, GL_DEPTH24_STENCIL8, GLsizei(width), GLsizei(height));
  glCreateFramebuffers(2, framebuffers_);
  glNamedFramebufferTexture(framebuffers_[0], GL_COLOR_ATTACHMENT0, attachments_[0], 0);
  glNamedFramebufferTexture(framebuffers_[0], GL_COLOR_ATTACHMENT1, attachments_[1], 0);
  glNamedFramebufferTexture(framebuffers_[0], GL_DEPTH_STENCIL_ATTACHMENT, attachments_[2], 0);
  const GLenum draw_buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(framebuffers_[0], 2, draw_buffers);
  glNamedFramebufferRenderbuffer(framebuffers_[1], GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                 renderbuffer_);
  if (glCheckNamedFramebufferStatus(framebuffers_[0], GL_DRAW_FRAMEBUFFER) !=
          GL_FRAMEBUFFER_COMPLETE ||
      glCheckNamedFramebufferStatus(framebuffers_[1], GL_READ_FRAMEBUFFER) !=
          GL_FRAMEBUFFER_COMPLETE)
    return "the engine's framebuffers are not complete";
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &custom_array_);
  glTextureStorage3D(custom_array_, 1, GL_RGBA8, 4, 4, 4);
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) return "creating the engine's objects: GL error " + std::to_string(e);
  apply();
  const GLenum applied = glGetError();
  return applied == GL_NO_ERROR ? "" : "applying the engine's state: GL error " +
                                           std::to_string(applied);
}

void HostState::apply() const {
  glUseProgram(program_);
  glBindVertexArray(vertex_array_);
  glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, feedback_);
  // Indexed bindings first: each also sets its generic binding, set last.
  const GLint uniforms = limit(GL_MAX_UNIFORM_BUFFER_BINDINGS, kUniformBindings);
  for (GLint i = 0; i < uniforms; ++i) {
    if (i % 2 == 0) glBindBufferBase(GL_UNIFORM_BUFFER, GLuint(i), buffers_[16 + i]);
    else glBindBufferRange(GL_UNIFORM_BUFFER, GLuint(i), buffers_[16 + i], uniform_alignment_, 256);
  }
  const GLint storage = limit(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, 32);
  for (GLint i = 0; i < storage; ++i) {
    if (i % 2 == 1) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(i), buffers_[32 + i]);
    else glBindBufferRange(GL_SHADER_STORAGE_BUFFER, GLuint(i), buffers_[32 + i],
                           storage_alignment_, 512);
  }
  for (GLuint i = 0; i < GLuint(kFeedbackBindings); ++i)
    glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, i, buffers_[40 + i], 4 * i, 1024);
  const GLenum generic[] = {GL_ARRAY_BUFFER,         GL_UNIFORM_BUFFER,
                            GL_SHADER_STORAGE_BUFFER, GL_DRAW_INDIRECT_BUFFER,
                            GL_DISPATCH_INDIRECT_BUFFER, GL_PIXEL_PACK_BUFFER,
                            GL_PIXEL_UNPACK_BUFFER,   GL_COPY_READ_BUFFER,
                            GL_COPY_WRITE_BUFFER,     GL_TRANSFORM_FEEDBACK_BUFFER,
                            GL_QUERY_BUFFER,          GL_ATOMIC_COUNTER_BUFFER,
                            GL_TEXTURE_BUFFER};
  for (size_t k = 0; k < sizeof(generic) / sizeof(generic[0]); ++k)
    glBindBuffer(generic[k], buffers_[2 + k]);
  for (int u = 0; u < kUnits; ++u) {
    glActiveTexture(GLenum(GL_TEXTURE0 + u));
    for (int t = 0; t < 5; ++t) glBindTexture(kTargets[t], textures_[u][t]);
    glBindSampler(GLuint(u), samplers_[u]);
  }
  glActiveTexture(GL_TEXTURE5);
  for (int i = 0; i < kImages; ++i)
    glBindImageTexture(GLuint(i), images_[i], i % 2, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffers_[0]);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffers_[1]);
  glBindRenderbuffer(GL_RENDERBUFFER, renderbuffer_);
  for (const Cap& c : kCaps) {
    if (c.host_value) glEnable(c.cap);
    else glDisable(c.cap);
  }
  glDepthFunc(GL_GEQUAL);
  glDepthMask(GL_FALSE);
  glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
  glCullFace(GL_FRONT);
  glFrontFace(GL_CW);
  glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE);
  glBlendEquation(GL_MAX);
  glStencilFunc(GL_NOTEQUAL, 3, 0xF0);
  glStencilMask(0x0F);
  glViewport(3, 5, GLsizei(width_) - 7, GLsizei(height_) - 9);
  glScissor(1, 2, GLsizei(width_) - 3, GLsizei(height_) - 4);
  glDepthRange(0.25, 0.75);
  glClearColor(0.1f, 0.2f, 0.3f, 0.4f);
  glClearDepth(0.625);
  glClearStencil(5);
  glPolygonOffset(1.5f, 2.0f);
  glPointSize(3.0f);
  glPrimitiveRestartIndex(7);
  glProvokingVertex(GL_FIRST_VERTEX_CONVENTION);
  glPatchParameteri(GL_PATCH_VERTICES, 4);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  const GLenum unpack[8] = {GL_UNPACK_SWAP_BYTES,  GL_UNPACK_LSB_FIRST,  GL_UNPACK_ROW_LENGTH,
                            GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_ROWS,  GL_UNPACK_SKIP_PIXELS,
                            GL_UNPACK_SKIP_IMAGES,  GL_UNPACK_ALIGNMENT};
  const GLenum pack[8] = {GL_PACK_SWAP_BYTES,  GL_PACK_LSB_FIRST,  GL_PACK_ROW_LENGTH,
                          GL_PACK_IMAGE_HEIGHT, GL_PACK_SKIP_ROWS,  GL_PACK_SKIP_PIXELS,
                          GL_PACK_SKIP_IMAGES,  GL_PACK_ALIGNMENT};
  const GLint values[8] = {1, 1, 7, 3, 1, 2, 1, 2};
  for (int k = 0; k < 8; ++k) {
    glPixelStorei(unpack[k], values[k]);
    glPixelStorei(pack[k], values[k]);
  }
}

void HostState::release() {
  if (program_ == 0) return;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDeleteProgram(program_);
  glDeleteVertexArrays(1, &vertex_array_);
  glDeleteBuffers(64, buffers_);
  for (auto& unit : textures_) glDeleteTextures(5, unit);
  glDeleteSamplers(kUnits, samplers_);
  glDeleteTextures(kImages, images_);
  glDeleteTransformFeedbacks(1, &feedback_);
  glDeleteRenderbuffers(1, &renderbuffer_);
  glDeleteFramebuffers(2, framebuffers_);
  glDeleteTextures(3, attachments_);
  glDeleteTextures(1, &custom_array_);
  *this = HostState();
}

}  // namespace host
