// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GL 4.5 back-end: palette texture, compact vertex format, persistently mapped record ring,
// one glDrawElementsInstanced per batch (B. Dudash, "Skinned Instancing", NVIDIA 2007), and the
// traditional and rigid baselines.
#include "si/gl/renderer.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include "core/str_cat.h"
#include "si/core/log.h"
#include "gl/glsl_parts.h"
#include "si/gl/skinning_glsl.h"

namespace si {
using detail::strCat;

namespace {

constexpr GLuint kNoObject = 0;
constexpr uint32_t kMaxTraditionalJoints = 1024;  // 48 KiB of rows: within any 64 KiB block.

// ---- Shaders --------------------------------------------------------------------------------
const char* kSkinnedMain = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_normal;
layout(location = 2) in vec2 a_texcoord;
layout(location = 3) in uvec4 a_joints;
layout(location = 4) in vec4 a_weights;
layout(location = 1) uniform mat4 u_view_projection;
out vec3 v_normal;
out vec2 v_texcoord;
flat out uint v_color;
#ifdef SI_CAPTURE
out vec3 tf_position;
#endif
void main() {
#if defined(SI_TRADITIONAL)
  vec4 m0 = vec4(0.0), m1 = vec4(0.0), m2 = vec4(0.0);
  for (int k = 0; k < 4; ++k) {
    float w = a_weights[k];
    if (w == 0.0) continue;
    uint j = a_joints[k] * 3u;
    m0 += w * si_joint_rows[j];
    m1 += w * si_joint_rows[j + 1u];
    m2 += w * si_joint_rows[j + 2u];
  }
  vec4 w0 = si_world_rows[0], w1 = si_world_rows[1], w2 = si_world_rows[2];
  uint color = si_color;
#else
  SiInstance inst = si_instances[gl_InstanceID];
#if defined(SI_RIGID)
  vec4 m0 = vec4(1, 0, 0, 0), m1 = vec4(0, 1, 0, 0), m2 = vec4(0, 0, 1, 0);
#else
  vec4 m0, m1, m2;
  siSkin(inst, a_joints, a_weights, m0, m1, m2);
#endif
  vec4 w0 = inst.world_rows[0], w1 = inst.world_rows[1], w2 = inst.world_rows[2];
  uint color = inst.blend.w;
#endif
  vec3 model = siTransformPoint(m0, m1, m2, a_position);
#ifdef SI_CAPTURE
  tf_position = model;
#endif
  vec3 world = siTransformPoint(w0, w1, w2, model);
  v_normal = siTransformNormal(w0, w1, w2, siTransformNormal(m0, m1, m2, a_normal.xyz));
  v_texcoord = a_texcoord;
  v_color = color;
  gl_Position = u_view_projection * vec4(world, 1.0);
}
)";

const char* kTraditionalDecl = R"(
layout(std140, binding = 1) uniform SiCharacter {
  vec4 si_world_rows[3];
  uint si_color;
  vec4 si_joint_rows[3 * SI_MAX_JOINTS];
};
)";

const char* kFragment = R"(#version 450 core
in vec3 v_normal;
in vec2 v_texcoord;
flat in uint v_color;
layout(binding = 1) uniform sampler2D u_base_color;
layout(location = 2) uniform vec4 u_base_factor;
layout(location = 3) uniform vec3 u_light_direction;
out vec4 o_color;
void main() {
  vec4 texel = texture(u_base_color, v_texcoord) * u_base_factor;
  vec4 tint = unpackUnorm4x8(v_color);
  // The texture's alpha is the tint mask: 1 takes the instance's colour, 0 keeps the texel.
  vec3 albedo = mix(texel.rgb, texel.rgb * tint.rgb, texel.a);
  float lambert = max(dot(normalize(v_normal), -u_light_direction), 0.0);
  o_color = vec4(albedo * (0.35 + 0.65 * lambert), 1.0);
}
)";
const char* kDepthFragment = "#version 450 core\nvoid main() {}\n";

// The CPU-skinning baseline: positions and normals arrive skinned, in camera-relative world space.
const char* kPreSkinnedVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_texcoord;
layout(location = 1) uniform mat4 u_view_projection;
layout(location = 4) uniform uint u_color;
out vec3 v_normal;
out vec2 v_texcoord;
flat out uint v_color;
void main() {
  v_normal = a_normal;
  v_texcoord = a_texcoord;
  v_color = u_color;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
}
)";

struct ProgramResult {
  GLuint program = kNoObject;
  Status status;
};

Status compile(GLenum type, const std::string& source, const char* name, GLuint* out) {
  const GLuint shader = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    return {StatusCode::kBackend, strCat("compiling the ", name, " ",
                                         type == GL_VERTEX_SHADER ? "vertex" : "fragment",
                                         " shader failed: ", log.c_str())};
  }
  *out = shader;
  return Status::ok();
}

// Compiles and links; `varying` non-null captures it with transform feedback.
Status link(const std::string& vs, const std::string& fs, const char* name, const char* varying,
            GLuint* out) {
  GLuint v = kNoObject, f = kNoObject;
  Status s = compile(GL_VERTEX_SHADER, vs, name, &v);
  if (!s.isOk()) return s;
  s = compile(GL_FRAGMENT_SHADER, fs, name, &f);
  if (!s.isOk()) {
    glDeleteShader(v);
    return s;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, v);
  glAttachShader(program, f);
  if (varying != nullptr) glTransformFeedbackVaryings(program, 1, &varying, GL_INTERLEAVED_ATTRIBS);
  glLinkProgram(program);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    glDeleteProgram(program);
    return {StatusCode::kBackend, strCat("linking the ", name, " program failed: ", log.c_str())};
  }
  *out = program;
  return Status::ok();
}

void GLAD_API_PTR debugCallback(GLenum, GLenum type, GLuint, GLenum severity, GLsizei,
                                const GLchar* message, const void*) {
  const LogLevel level = type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH
                             ? LogLevel::kError
                         : severity == GL_DEBUG_SEVERITY_MEDIUM ? LogLevel::kWarning
                                                                : LogLevel::kDebug;
  logMessage(level, strCat("GL: ", message));
}

uint32_t packNormal(const glm::vec3& n) {
  const auto c = [](float v) {
    return uint32_t(int32_t(std::lround(std::clamp(v, -1.0f, 1.0f) * 511.0f)) & 0x3FF);
  };
  return c(n.x) | (c(n.y) << 10) | (c(n.z) << 20);
}

// What the instanced shader computes for palette slot `slot` of `rec`: clip A's frames lerped,
// crossfaded towards clip B by the record's weight (float bits in blend.x, y, z).
glm::mat4 recordJointMatrix(const BakedPalette& palette, const InstanceRecord& rec, uint32_t slot) {
  float fa, fb, wb;
  std::memcpy(&fa, &rec.blend[0], 4);
  std::memcpy(&fb, &rec.blend[1], 4);
  std::memcpy(&wb, &rec.blend[2], 4);
  glm::mat4 mat = emulateFrameMatrix(palette, rec.frames[0], rec.frames[1], fa, slot);
  if (wb > 0.0f)
    mat = mat * (1.0f - wb) + emulateFrameMatrix(palette, rec.frames[2], rec.frames[3], fb, slot) * wb;
  return mat;
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// A program and which of the shared uniforms it declares (-1: absent; setting an absent location
// is GL_INVALID_OPERATION).
struct Program {
  GLuint id = kNoObject;
  GLint palette_info = -1, view_projection = -1, base_factor = -1, light_direction = -1;
};

Program describe(GLuint id) {
  Program p;
  p.id = id;
  if (id == kNoObject) return p;
  p.palette_info = glGetUniformLocation(id, "si_palette_info");
  p.view_projection = glGetUniformLocation(id, "u_view_projection");
  p.base_factor = glGetUniformLocation(id, "u_base_factor");
  p.light_direction = glGetUniformLocation(id, "u_light_direction");
  return p;
}

struct Renderer::Impl {
  GlInfo info;
  RendererDesc desc;
  bool debug = false;
  uint32_t block_size = 0, capacity = 0, alignment = 256;
  Program skinned, depth, rigid, traditional, capture, preskinned;
  // CPU-skinning baseline: a streaming vertex buffer and the vertex range of each LOD range.
  GLuint cpu_vao = kNoObject, cpu_stream = kNoObject;
  size_t cpu_stream_size = 0;
  std::vector<uint8_t> cpu_vertices;
  std::vector<glm::uvec2> lod_vertex_ranges;  // Per (sub-mesh, lod): first vertex, count.
  std::vector<std::vector<uint32_t>> lod_range_index;  // [sub_mesh][lod] -> lod_vertex_ranges.
  SkinnedMesh mesh_copy;
  // Palette.
  GLuint palette_texture = kNoObject;
  glm::uvec4 palette_info{0};
  const BakedPalette* palette = nullptr;
  uint32_t palette_slots = 0;
  // Character.
  GLuint vao = kNoObject, vertex_buffer = kNoObject, index_buffer = kNoObject;
  GLuint base_texture = kNoObject;
  glm::vec4 base_factor{1.0f};
  std::vector<SubMesh> sub_meshes;
  uint32_t vertex_count = 0;
  // Record ring.
  GLuint ring = kNoObject;
  uint8_t* ring_mapped = nullptr;
  size_t region_size = 0, ring_size = 0;
  uint32_t ring_frames = 3, ring_index = 0;
  std::vector<GLsync> fences;
  std::vector<DrawBatch> draws;
  // Traditional path.
  GLuint character_ubo = kNoObject;
  std::vector<uint8_t> character_block;
  GLuint timer = kNoObject;

  Status check(const char* what) const { return debug ? checkGlErrors(what) : Status::ok(); }

  Status ensureRing(size_t bytes_per_frame) {
    // Each region ends with one block of slack so a bound range of the full block size stays
    // inside the buffer.
    const size_t need = (bytes_per_frame + alignment - 1) / alignment * alignment + block_size;
    if (ring != kNoObject && need <= region_size) return Status::ok();
    for (GLsync& f : fences)
      if (f) {
        glClientWaitSync(f, GL_SYNC_FLUSH_COMMANDS_BIT, GLuint64(1e10));
        glDeleteSync(f);
        f = nullptr;
      }
    if (ring != kNoObject) {
      glUnmapNamedBuffer(ring);
      glDeleteBuffers(1, &ring);
    }
    region_size = std::max<size_t>(need * 2, size_t(1) << 20);  // Grow geometrically.
    region_size = (region_size + alignment - 1) / alignment * alignment;
    ring_size = region_size * ring_frames;
    glCreateBuffers(1, &ring);
    const GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    glNamedBufferStorage(ring, GLsizeiptr(ring_size), nullptr, flags);
    ring_mapped = static_cast<uint8_t*>(glMapNamedBufferRange(ring, 0, GLsizeiptr(ring_size), flags));
    if (ring_mapped == nullptr)
      return {StatusCode::kBackend, "mapping the instance record ring failed"};
    fences.assign(ring_frames, nullptr);
    return check("creating the instance record ring");
  }

  // Waits until the GPU is done with region `r` (it was used ring_frames frames ago).
  void acquireRegion(uint32_t r) {
    if (fences[r]) {
      glClientWaitSync(fences[r], GL_SYNC_FLUSH_COMMANDS_BIT, GLuint64(1e10));
      glDeleteSync(fences[r]);
      fences[r] = nullptr;
    }
  }

  void bindCommon(const Program& program, const Camera& camera, const glm::vec3& light) {
    glUseProgram(program.id);
    glBindVertexArray(vao);
    glBindTextureUnit(0, palette_texture);
    glBindTextureUnit(1, base_texture);
    const glm::mat4 vp = camera.viewProjection();
    if (program.palette_info >= 0)
      glProgramUniform4uiv(program.id, program.palette_info, 1, &palette_info[0]);
    if (program.view_projection >= 0)
      glProgramUniformMatrix4fv(program.id, program.view_projection, 1, GL_FALSE, &vp[0][0]);
    if (program.base_factor >= 0)
      glProgramUniform4fv(program.id, program.base_factor, 1, &base_factor[0]);
    if (program.light_direction >= 0)
      glProgramUniform3fv(program.id, program.light_direction, 1, &light[0]);
  }

  void beginTimer(DrawStats* stats) {
    if (desc.measure_gpu_time && stats != nullptr) glBeginQuery(GL_TIME_ELAPSED, timer);
  }
  void endTimer(DrawStats* stats) {
    if (!desc.measure_gpu_time || stats == nullptr) return;
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timer, GL_QUERY_RESULT, &ns);
    stats->gpu_ms = double(ns) * 1e-6;
  }

  IndexRange lodRange(uint32_t sub_mesh, uint32_t lod) const {
    const std::vector<IndexRange>& lods = sub_meshes[sub_mesh].lods;
    return lods[std::min<size_t>(lod, lods.size() - 1)];
  }
};

Renderer::Renderer() = default;
Renderer::~Renderer() { shutdown(); }

Status Renderer::init(const GlInfo& info, const RendererDesc& desc) {
  shutdown();
  auto impl = std::make_unique<Impl>();
  impl->info = info;
  impl->desc = desc;
#ifdef NDEBUG
  impl->debug = desc.debug_checks == 1;
#else
  impl->debug = desc.debug_checks != 2;
#endif
  const uint32_t limit = std::min<uint32_t>(info.max_uniform_block_size_bytes, 1u << 20);
  impl->block_size = desc.uniform_block_size_bytes == 0 ? limit : desc.uniform_block_size_bytes;
  if (impl->block_size < 16384 || impl->block_size > limit)
    return {StatusCode::kInvalidArgument,
            strCat("RendererDesc.uniform_block_size_bytes ", impl->block_size,
                   " must be within 16384 and the context's limit ", limit)};
  impl->capacity = impl->block_size / kInstanceRecordSize;
  impl->alignment = std::max<uint32_t>(16, info.uniform_buffer_offset_alignment);
  impl->ring_frames = desc.ring_frames == 0 ? 3 : desc.ring_frames;
  if (impl->debug && info.has_khr_debug) {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(&debugCallback, nullptr);
  }
  const std::string header = strCat("#version 450 core\n#define SI_MAX_INSTANCES ",
                                    impl->capacity, "\n#define SI_MAX_JOINTS ",
                                    kMaxTraditionalJoints, "\n");
  const std::string include = skinningGlsl();
  GLuint ids[6] = {kNoObject, kNoObject, kNoObject, kNoObject, kNoObject, kNoObject};
  Status s = link(header + include + kSkinnedMain, kFragment, "skinned", nullptr, &ids[0]);
  if (s.isOk())
    s = link(header + include + kSkinnedMain, kDepthFragment, "depth-only", nullptr, &ids[1]);
  if (s.isOk())
    s = link(header + "#define SI_RIGID\n" + include + kSkinnedMain, kFragment, "rigid", nullptr,
             &ids[2]);
  if (s.isOk())
    s = link(header + "#define SI_TRADITIONAL\n" + kTraditionalDecl + transformGlsl() + kSkinnedMain,
             kFragment,
             "traditional", nullptr, &ids[3]);
  if (s.isOk())
    s = link(header + "#define SI_CAPTURE\n" + include + kSkinnedMain, kDepthFragment, "capture",
             "tf_position", &ids[4]);
  if (s.isOk()) s = link(kPreSkinnedVertex, kFragment, "pre-skinned", nullptr, &ids[5]);
  impl->preskinned = describe(ids[5]);
  impl->skinned = describe(ids[0]);
  impl->depth = describe(ids[1]);
  impl->rigid = describe(ids[2]);
  impl->traditional = describe(ids[3]);
  impl->capture = describe(ids[4]);
  if (s.isOk()) {
    glCreateQueries(GL_TIME_ELAPSED, 1, &impl->timer);
    glCreateBuffers(1, &impl->character_ubo);
    // std140: 3 vec4 world rows, a uint padded to 16, then the joint rows.
    impl->character_block.assign(48 + 16 + size_t(kMaxTraditionalJoints) * 48, 0);
    glNamedBufferStorage(impl->character_ubo, GLsizeiptr(impl->character_block.size()), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    s = impl->check("Renderer::init");
  }
  impl_ = std::move(impl);
  if (!s.isOk()) shutdown();
  return s;
}

void Renderer::shutdown() {
  if (!impl_) return;
  Impl& m = *impl_;
  for (GLsync f : m.fences)
    if (f) glDeleteSync(f);
  if (m.ring != kNoObject) {
    glUnmapNamedBuffer(m.ring);
    glDeleteBuffers(1, &m.ring);
  }
  for (const Program* p : {&m.skinned, &m.depth, &m.rigid, &m.traditional, &m.capture,
                           &m.preskinned})
    if (p->id != kNoObject) glDeleteProgram(p->id);
  if (m.cpu_vao != kNoObject) glDeleteVertexArrays(1, &m.cpu_vao);
  if (m.cpu_stream != kNoObject) glDeleteBuffers(1, &m.cpu_stream);
  const GLuint buffers[] = {m.vertex_buffer, m.index_buffer, m.character_ubo};
  glDeleteBuffers(3, buffers);
  const GLuint textures[] = {m.palette_texture, m.base_texture};
  glDeleteTextures(2, textures);
  if (m.vao != kNoObject) glDeleteVertexArrays(1, &m.vao);
  if (m.timer != kNoObject) glDeleteQueries(1, &m.timer);
  impl_.reset();
}

BatchLimits Renderer::batchLimits() const {
  BatchLimits l;
  if (!impl_) return l;
  l.max_uniform_block_size_bytes = impl_->block_size;
  l.uniform_buffer_offset_alignment = impl_->alignment;
  return l;
}

Status Renderer::uploadPalette(const BakedPalette& palette) {
  if (!impl_) return {StatusCode::kInvalidArgument, "Renderer: init() first"};
  Impl& m = *impl_;
  const PaletteLayout& l = palette.layout;
  if (palette.texel_bytes.size() != l.textureTexelCount() * bytesPerTexel(palette.format))
    return {StatusCode::kInvalidArgument, "uploadPalette: texel data does not match the layout"};
  if (l.width > m.info.max_texture_size || l.height > m.info.max_texture_size)
    return {StatusCode::kLimitExceeded,
            strCat("uploadPalette: the palette is ", l.width, "x", l.height,
                   ", GL_MAX_TEXTURE_SIZE is ", m.info.max_texture_size,
                   " (bake with BakeDesc::max_texture_size)")};
  if (m.palette_texture != kNoObject) glDeleteTextures(1, &m.palette_texture);
  const bool half = palette.format == PaletteFormat::kMatrix3x4F16;
  glCreateTextures(GL_TEXTURE_2D, 1, &m.palette_texture);
  glTextureStorage2D(m.palette_texture, 1, half ? GL_RGBA16F : GL_RGBA32F, GLsizei(l.width),
                     GLsizei(l.height));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(m.palette_texture, 0, 0, 0, GLsizei(l.width), GLsizei(l.height), GL_RGBA,
                      half ? GL_HALF_FLOAT : GL_FLOAT, palette.texel_bytes.data());
  glTextureParameteri(m.palette_texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(m.palette_texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  m.palette_info = glm::uvec4(l.width_log2, l.joint_stride_texels,
                              palette.format == PaletteFormat::kQuatTranslationF32 ? 1u : 0u, 0u);
  m.palette = &palette;
  m.palette_slots = l.joint_count;
  return m.check("uploadPalette");
}

Status Renderer::uploadCharacter(const Character& character, const BakedPalette& palette) {
  if (!impl_) return {StatusCode::kInvalidArgument, "Renderer: init() first"};
  Impl& m = *impl_;
  const SkinnedMesh& mesh = character.mesh;
  Status s = mesh.validate(character.skeleton.jointCount());
  if (!s.isOk()) return s;
  if (palette.skeleton_to_palette.size() != character.skeleton.jointCount())
    return {StatusCode::kInvalidArgument,
            "uploadCharacter: the palette was baked for another skeleton"};
  const bool wide = palette.palette_joints.size() > 256;
  const size_t stride = wide ? 36 : 32;
  std::vector<uint8_t> vertices(mesh.vertexCount() * stride);
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    uint8_t* out = vertices.data() + v * stride;
    std::memcpy(out, &mesh.positions[v], 12);
    const uint32_t n = packNormal(mesh.normals[v]);
    std::memcpy(out + 12, &n, 4);
    const glm::vec2 uv = mesh.texcoords.empty() ? glm::vec2(0.0f) : mesh.texcoords[v];
    const uint16_t h[2] = {floatToHalf(uv.x), floatToHalf(uv.y)};
    std::memcpy(out + 16, h, 4);
    uint16_t slots[4] = {0, 0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      if (mesh.weights[v][k] == 0.0f) continue;
      const int32_t slot = palette.skeleton_to_palette[mesh.joints[v][k]];
      if (slot < 0)
        return {StatusCode::kInvalidArgument,
                strCat("uploadCharacter: vertex ", v, " is weighted to joint ", mesh.joints[v][k],
                       ", which the palette does not store")};
      slots[k] = uint16_t(slot);
    }
    if (wide) {
      std::memcpy(out + 20, slots, 8);
    } else {
      const uint8_t narrow[4] = {uint8_t(slots[0]), uint8_t(slots[1]), uint8_t(slots[2]),
                                 uint8_t(slots[3])};
      std::memcpy(out + 20, narrow, 4);
    }
    const glm::u16vec4 w = quantizeWeights(mesh.weights[v]);
    std::memcpy(out + (wide ? 28 : 24), &w, 8);
  }
  if (m.vao != kNoObject) glDeleteVertexArrays(1, &m.vao);
  const GLuint old[] = {m.vertex_buffer, m.index_buffer};
  glDeleteBuffers(2, old);
  glCreateBuffers(1, &m.vertex_buffer);
  glNamedBufferStorage(m.vertex_buffer, GLsizeiptr(vertices.size()), vertices.data(), 0);
  glCreateBuffers(1, &m.index_buffer);
  glNamedBufferStorage(m.index_buffer, GLsizeiptr(mesh.indices.size() * 4), mesh.indices.data(), 0);
  glCreateVertexArrays(1, &m.vao);
  glVertexArrayVertexBuffer(m.vao, 0, m.vertex_buffer, 0, GLsizei(stride));
  glVertexArrayElementBuffer(m.vao, m.index_buffer);
  const auto attrib = [&](GLuint loc) {
    glEnableVertexArrayAttrib(m.vao, loc);
    glVertexArrayAttribBinding(m.vao, loc, 0);
  };
  attrib(0);
  glVertexArrayAttribFormat(m.vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  attrib(1);
  glVertexArrayAttribFormat(m.vao, 1, 4, GL_INT_2_10_10_10_REV, GL_TRUE, 12);
  attrib(2);
  glVertexArrayAttribFormat(m.vao, 2, 2, GL_HALF_FLOAT, GL_FALSE, 16);
  attrib(3);
  glVertexArrayAttribIFormat(m.vao, 3, 4, wide ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE, 20);
  attrib(4);
  glVertexArrayAttribFormat(m.vao, 4, 4, GL_UNSIGNED_SHORT, GL_TRUE, wide ? 28 : 24);
  m.sub_meshes = mesh.sub_meshes;
  m.vertex_count = uint32_t(mesh.vertexCount());
  m.mesh_copy = mesh;
  m.lod_vertex_ranges.clear();
  m.lod_range_index.assign(mesh.sub_meshes.size(), {});
  for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm)
    for (const IndexRange& r : mesh.sub_meshes[sm].lods) {
      uint32_t lo = UINT32_MAX, hi = 0;
      for (uint32_t i = r.first_index; i < r.first_index + r.index_count; ++i) {
        lo = std::min(lo, mesh.indices[i]);
        hi = std::max(hi, mesh.indices[i]);
      }
      m.lod_range_index[sm].push_back(uint32_t(m.lod_vertex_ranges.size()));
      m.lod_vertex_ranges.push_back(glm::uvec2(lo, hi - lo + 1));
    }
  if (m.cpu_vao != kNoObject) glDeleteVertexArrays(1, &m.cpu_vao);
  glCreateVertexArrays(1, &m.cpu_vao);
  glVertexArrayElementBuffer(m.cpu_vao, m.index_buffer);
  for (GLuint loc : {0u, 1u, 2u}) {
    glEnableVertexArrayAttrib(m.cpu_vao, loc);
    glVertexArrayAttribBinding(m.cpu_vao, loc, 0);
  }
  glVertexArrayAttribFormat(m.cpu_vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribFormat(m.cpu_vao, 1, 3, GL_FLOAT, GL_FALSE, 12);
  glVertexArrayAttribFormat(m.cpu_vao, 2, 2, GL_FLOAT, GL_FALSE, 24);

  // Base colour: the first material's factor and image; white (alpha 1: tint everywhere) if none.
  m.base_factor = character.materials.empty() ? glm::vec4(1.0f)
                                              : character.materials[0].base_color_factor;
  const Image* image = nullptr;
  if (!character.materials.empty() && character.materials[0].base_color_image >= 0)
    image = &character.images[size_t(character.materials[0].base_color_image)];
  const uint8_t white[4] = {255, 255, 255, 255};
  if (m.base_texture != kNoObject) glDeleteTextures(1, &m.base_texture);
  glCreateTextures(GL_TEXTURE_2D, 1, &m.base_texture);
  const GLsizei w = image ? GLsizei(image->width) : 1, h = image ? GLsizei(image->height) : 1;
  const GLsizei levels = GLsizei(std::floor(std::log2(double(std::max(w, h))))) + 1;
  glTextureStorage2D(m.base_texture, levels, GL_RGBA8, w, h);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(m.base_texture, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE,
                      image ? image->rgba8.data() : white);
  glGenerateTextureMipmap(m.base_texture);
  glTextureParameteri(m.base_texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(m.base_texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  return m.check("uploadCharacter");
}

uint32_t Renderer::triangleCount(uint32_t sub_mesh, uint32_t lod) const {
  if (!impl_ || sub_mesh >= impl_->sub_meshes.size()) return 0;
  return impl_->lodRange(sub_mesh, lod).index_count / 3;
}

void Renderer::clear(const glm::vec4& color) {
  glClearColor(color.r, color.g, color.b, color.a);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

Status Renderer::drawCrowd(const CrowdManager& crowd, const InstanceBatcher& batcher,
                           const Camera& camera, DrawStats* stats, DrawMode mode) {
  if (!impl_ || impl_->vao == kNoObject || impl_->palette_texture == kNoObject)
    return {StatusCode::kInvalidArgument, "drawCrowd: init, uploadPalette and uploadCharacter first"};
  Impl& m = *impl_;
  if (batcher.capacityPerDraw() > m.capacity)
    return {StatusCode::kInvalidArgument,
            strCat("drawCrowd: the batcher's ", batcher.capacityPerDraw(),
                   " instances per draw exceed the shader's ", m.capacity,
                   " (init the batcher with batchLimits())")};
  const auto t0 = std::chrono::steady_clock::now();
  Status s = m.ensureRing(batcher.recordBufferBound(crowd));
  if (!s.isOk()) return s;
  const uint32_t r = m.ring_index;
  m.acquireRegion(r);
  const size_t base = size_t(r) * m.region_size;
  s = batcher.build(crowd, Span<uint8_t>(m.ring_mapped + base, m.region_size - m.block_size),
                    &m.draws);
  if (!s.isOk()) return s;
  const Program& program = mode == DrawMode::kDepthOnly ? m.depth
                           : mode == DrawMode::kRigid   ? m.rigid
                                                        : m.skinned;
  m.bindCommon(program, camera, light_direction_);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  if (mode == DrawMode::kDepthOnly) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  m.beginTimer(stats);
  DrawStats st;
  for (const DrawBatch& d : m.draws) {
    if (d.sub_mesh >= m.sub_meshes.size()) continue;
    const IndexRange range = m.lodRange(d.sub_mesh, d.lod);
    glBindBufferRange(GL_UNIFORM_BUFFER, 0, m.ring, GLintptr(base + d.byte_offset),
                      GLsizeiptr(m.block_size));
    glDrawElementsInstanced(GL_TRIANGLES, GLsizei(range.index_count), GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(uintptr_t(range.first_index) * 4),
                            GLsizei(d.instance_count));
    ++st.draw_calls;
    st.triangles += uint64_t(range.index_count / 3) * d.instance_count;
    st.instances += d.instance_count;
  }
  st.cpu_submit_ms = msSince(t0);  // Before the (blocking) timer read.
  m.endTimer(stats);
  if (mode == DrawMode::kDepthOnly) glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  m.fences[r] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  m.ring_index = (r + 1) % m.ring_frames;
  s = m.check("drawCrowd");
  if (stats != nullptr) {
    st.gpu_ms = stats->gpu_ms;
    if (!m.desc.measure_gpu_time) st.gpu_ms = -1.0;
    *stats = st;
  }
  return s;
}

Status Renderer::drawTraditional(const CrowdManager& crowd, const Camera& camera,
                                 DrawStats* stats) {
  if (!impl_ || impl_->vao == kNoObject || impl_->palette_texture == kNoObject)
    return {StatusCode::kInvalidArgument,
            "drawTraditional: init, uploadPalette and uploadCharacter first"};
  Impl& m = *impl_;
  if (m.palette_slots > kMaxTraditionalJoints)
    return {StatusCode::kLimitExceeded, "drawTraditional: more joints than the uniform block holds"};
  const auto t0 = std::chrono::steady_clock::now();
  m.bindCommon(m.traditional, camera, light_direction_);
  glBindBufferBase(GL_UNIFORM_BUFFER, 1, m.character_ubo);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  m.beginTimer(stats);
  DrawStats st;
  const std::vector<InstanceRecord>& records = crowd.records();
  const uint32_t sub_meshes = crowd.desc().sub_mesh_count;
  const size_t block_bytes = 64 + size_t(m.palette_slots) * 48;
  for (size_t v = 0; v < records.size(); ++v) {
    const InstanceRecord& rec = records[v];
    uint8_t* block = m.character_block.data();
    std::memcpy(block, rec.world_rows, 48);
    std::memcpy(block + 48, &rec.blend[3], 4);
    // The CPU does what the instanced shader does per vertex, once per joint per character.
    for (uint32_t slot = 0; slot < m.palette_slots; ++slot) {
      const glm::mat4 mat = recordJointMatrix(*m.palette, rec, slot);
      float rows[12];
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) rows[row * 4 + col] = mat[col][row];
      std::memcpy(block + 64 + size_t(slot) * 48, rows, 48);
    }
    glNamedBufferSubData(m.character_ubo, 0, GLsizeiptr(block_bytes), block);
    // This instance's worn sub-meshes at its LOD: from the crowd's buckets.
    uint32_t lod = 0;
    if (!crowd.lodOf(crowd.visibleHandles()[v], &lod).isOk()) continue;
    InstanceDesc desc;
    if (!crowd.get(crowd.visibleHandles()[v], &desc).isOk()) continue;
    for (uint32_t sm = 0; sm < sub_meshes && sm < m.sub_meshes.size(); ++sm) {
      if (!((desc.variation_mask >> sm) & 1u)) continue;
      const IndexRange range = m.lodRange(sm, lod);
      glDrawElements(GL_TRIANGLES, GLsizei(range.index_count), GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(uintptr_t(range.first_index) * 4));
      ++st.draw_calls;
      st.triangles += range.index_count / 3;
      ++st.instances;
    }
  }
  st.cpu_submit_ms = msSince(t0);  // Before the (blocking) timer read.
  m.endTimer(stats);
  Status s = m.check("drawTraditional");
  if (stats != nullptr) {
    st.gpu_ms = m.desc.measure_gpu_time ? stats->gpu_ms : -1.0;
    *stats = st;
  }
  return s;
}

Status Renderer::drawCpuSkinned(const CrowdManager& crowd, const Camera& camera,
                                 DrawStats* stats) {
  if (!impl_ || impl_->vao == kNoObject || impl_->palette_texture == kNoObject)
    return {StatusCode::kInvalidArgument,
            "drawCpuSkinned: init, uploadPalette and uploadCharacter first"};
  Impl& m = *impl_;
  const auto t0 = std::chrono::steady_clock::now();
  constexpr size_t kVertexBytes = 32;  // Position, normal, texcoord as floats.
  constexpr size_t kChunkBytes = size_t(8) << 20;
  if (m.cpu_stream == kNoObject) {
    glCreateBuffers(1, &m.cpu_stream);
    m.cpu_stream_size = kChunkBytes;
    glNamedBufferData(m.cpu_stream, GLsizeiptr(m.cpu_stream_size), nullptr, GL_STREAM_DRAW);
    glVertexArrayVertexBuffer(m.cpu_vao, 0, m.cpu_stream, 0, GLsizei(kVertexBytes));
  }
  glUseProgram(m.preskinned.id);
  glBindVertexArray(m.cpu_vao);
  glBindTextureUnit(1, m.base_texture);
  const glm::mat4 vp = camera.viewProjection();
  glProgramUniformMatrix4fv(m.preskinned.id, 1, 1, GL_FALSE, &vp[0][0]);
  glProgramUniform4fv(m.preskinned.id, 2, 1, &m.base_factor[0]);
  glProgramUniform3fv(m.preskinned.id, 3, 1, &light_direction_[0]);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  m.beginTimer(stats);
  DrawStats st;
  const SkinnedMesh& mesh = m.mesh_copy;
  std::vector<glm::mat4> joint(m.palette->skeleton_to_palette.size(), glm::mat4(1.0f));
  struct PendingDraw {
    IndexRange range;
    GLint base_vertex;
    uint32_t color;
  };
  std::vector<PendingDraw> pending;
  m.cpu_vertices.clear();
  const auto flush = [&] {
    if (m.cpu_vertices.empty()) return;
    glInvalidateBufferData(m.cpu_stream);  // Orphan: the GPU may still read the last chunk.
    glNamedBufferSubData(m.cpu_stream, 0, GLsizeiptr(m.cpu_vertices.size()), m.cpu_vertices.data());
    for (const PendingDraw& d : pending) {
      glProgramUniform1ui(m.preskinned.id, 4, d.color);
      glDrawElementsBaseVertex(GL_TRIANGLES, GLsizei(d.range.index_count), GL_UNSIGNED_INT,
                               reinterpret_cast<const void*>(uintptr_t(d.range.first_index) * 4),
                               d.base_vertex);
      ++st.draw_calls;
      st.triangles += d.range.index_count / 3;
      ++st.instances;
    }
    pending.clear();
    m.cpu_vertices.clear();
  };
  const std::vector<InstanceRecord>& records = crowd.records();
  for (size_t v = 0; v < records.size(); ++v) {
    const InstanceRecord& rec = records[v];
    uint32_t lod = 0;
    InstanceDesc desc;
    if (!crowd.lodOf(crowd.visibleHandles()[v], &lod).isOk() ||
        !crowd.get(crowd.visibleHandles()[v], &desc).isOk())
      continue;
    glm::mat4 world(1.0f);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) world[col][row] = rec.world_rows[row][col];
    for (size_t j = 0; j < joint.size(); ++j) {
      const int32_t slot = m.palette->skeleton_to_palette[j];
      if (slot < 0) continue;
      joint[j] = world * recordJointMatrix(*m.palette, rec, uint32_t(slot));
    }
    for (uint32_t sm = 0; sm < m.sub_meshes.size() && sm < 32; ++sm) {
      if (!((desc.variation_mask >> sm) & 1u)) continue;
      const size_t lod_index = std::min<size_t>(lod, m.sub_meshes[sm].lods.size() - 1);
      const glm::uvec2 vr = m.lod_vertex_ranges[m.lod_range_index[sm][lod_index]];
      if (m.cpu_vertices.size() + size_t(vr.y) * kVertexBytes > kChunkBytes) flush();
      const GLint first = GLint(m.cpu_vertices.size() / kVertexBytes);
      m.cpu_vertices.resize(m.cpu_vertices.size() + size_t(vr.y) * kVertexBytes);
      float* out = reinterpret_cast<float*>(m.cpu_vertices.data() + size_t(first) * kVertexBytes);
      for (uint32_t k = 0; k < vr.y; ++k, out += 8) {
        const uint32_t vi = vr.x + k;
        glm::mat4 blended(0.0f);
        for (int i = 0; i < 4; ++i) {
          const float w = mesh.weights[vi][i];
          if (w != 0.0f) blended += joint[mesh.joints[vi][i]] * w;
        }
        const glm::vec3 p(blended * glm::vec4(mesh.positions[vi], 1.0f));
        const glm::vec3 n = glm::normalize(glm::mat3(blended) * mesh.normals[vi]);
        const glm::vec2 uv = mesh.texcoords.empty() ? glm::vec2(0.0f) : mesh.texcoords[vi];
        const float values[8] = {p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y};
        std::memcpy(out, values, sizeof(values));
      }
      pending.push_back({m.sub_meshes[sm].lods[lod_index], first - GLint(vr.x), rec.blend[3]});
    }
  }
  flush();
  st.cpu_submit_ms = msSince(t0);
  m.endTimer(stats);
  Status s = m.check("drawCpuSkinned");
  if (stats != nullptr) {
    st.gpu_ms = m.desc.measure_gpu_time ? stats->gpu_ms : -1.0;
    *stats = st;
  }
  return s;
}

Status Renderer::captureSkinnedPositions(const InstanceRecord& record, std::vector<glm::vec3>* out) {
  if (!impl_ || impl_->vao == kNoObject || impl_->palette_texture == kNoObject || out == nullptr)
    return {StatusCode::kInvalidArgument,
            "captureSkinnedPositions: init, uploads first, and a non-null output"};
  Impl& m = *impl_;
  GLuint ubo = kNoObject, tf = kNoObject;
  glCreateBuffers(1, &ubo);
  std::vector<uint8_t> block(m.block_size, 0);
  std::memcpy(block.data(), &record, sizeof(record));
  glNamedBufferStorage(ubo, GLsizeiptr(block.size()), block.data(), 0);
  glCreateBuffers(1, &tf);
  glNamedBufferStorage(tf, GLsizeiptr(size_t(m.vertex_count) * 12), nullptr, GL_MAP_READ_BIT);
  Camera identity;  // Model space out: the capture reads positions before the world transform.
  m.bindCommon(m.capture, identity, light_direction_);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, ubo);
  glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, tf);
  glEnable(GL_RASTERIZER_DISCARD);
  glBeginTransformFeedback(GL_POINTS);
  glDrawArraysInstanced(GL_POINTS, 0, GLsizei(m.vertex_count), 1);
  glEndTransformFeedback();
  glDisable(GL_RASTERIZER_DISCARD);
  out->resize(m.vertex_count);
  glGetNamedBufferSubData(tf, 0, GLsizeiptr(size_t(m.vertex_count) * 12), out->data());
  glDeleteBuffers(1, &ubo);
  glDeleteBuffers(1, &tf);
  return checkGlErrors("captureSkinnedPositions");
}

}  // namespace si
