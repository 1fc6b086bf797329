// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GL 4.5 back-end: palette texture, compact vertex format, persistently mapped record ring,
// one glDrawElementsInstanced per batch (B. Dudash, "Skinned Instancing", NVIDIA 2007), and the
// traditional and rigid baselines.
#include "si/gl/renderer.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/str_cat.h"
#include "si/core/log.h"
#include "gl/glsl_parts.h"
#include "gl/renderer_impl.h"
#include "si/gl/skinning_glsl.h"

namespace si {
using detail::strCat;
using detail::link;
using detail::linkCompute;

namespace {

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
#ifdef SI_GPU_DRIVEN
// GPU-driven culling: the record of this draw's instance, through its bucket entry; a_entry is
// baseInstance + gl_InstanceID (an identity buffer with divisor 1).
layout(location = 5) in uint a_entry;
layout(std430, binding = 4) readonly buffer SiRecords { SiInstance si_records[]; };
layout(std430, binding = 5) readonly buffer SiEntries { uint si_entries[]; };
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
#if defined(SI_GPU_DRIVEN)
  SiInstance inst = si_records[si_entries[a_entry]];
#else
  SiInstance inst = si_instances[gl_InstanceID];
#endif
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

// ---- Compute pre-skinning: the skinning pass and the vertex-pulling draw ----------------------
// Shared declarations: the raw vertex buffer (32 or 36 bytes a vertex, read as words), the
// compacted vertex list of each (sub-mesh, LOD) and the pre-skinned ring (16 bytes a vertex:
// camera-relative world position, octahedral normal as 2 x snorm16).
// u_chunk: x first ring vertex of the draw, y vertices of the LOD, z offset into the LOD vertex
// list, w first instance of the batch; u_layout: x instances, y words per source vertex.
const char* kPreSkinDecl = R"(
layout(std430, binding = 2) readonly buffer SiSourceVertices { uint si_source[]; };
layout(std430, binding = 3) readonly buffer SiLodVertices { uint si_lod_vertices[]; };
layout(location = 5) uniform uvec4 u_chunk;
layout(location = 6) uniform uvec2 u_layout;
)";

const char* kComputeSkin = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 1) writeonly buffer SiSkinnedOut { vec4 si_skinned_out[]; };
vec2 siOctEncode(vec3 n) {
  n /= abs(n.x) + abs(n.y) + abs(n.z);
  vec2 e = n.xy;
  if (n.z < 0.0) e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return e;
}
void main() {
  uint g = gl_GlobalInvocationID.x;
  uint i = g / u_chunk.y;
  if (i >= u_layout.x) return;
  uint k = g - i * u_chunk.y;
  uint base = si_lod_vertices[u_chunk.z + k] * u_layout.y;
  vec3 p = vec3(uintBitsToFloat(si_source[base]), uintBitsToFloat(si_source[base + 1u]),
                uintBitsToFloat(si_source[base + 2u]));
  int normal_bits = int(si_source[base + 3u]);
  // GL_INT_2_10_10_10_REV, normalized: what the vertex-shader path's attribute fetch computes.
  vec3 n = max(vec3(bitfieldExtract(normal_bits, 0, 10), bitfieldExtract(normal_bits, 10, 10),
                    bitfieldExtract(normal_bits, 20, 10)) / 511.0, vec3(-1.0));
  uvec4 joints;
  vec4 weights;
  if (u_layout.y == 8u) {
    joints = uvec4(unpackUnorm4x8(si_source[base + 5u]) * 255.0 + 0.5);
    weights = vec4(unpackUnorm2x16(si_source[base + 6u]), unpackUnorm2x16(si_source[base + 7u]));
  } else {
    uint j01 = si_source[base + 5u], j23 = si_source[base + 6u];
    joints = uvec4(j01 & 0xFFFFu, j01 >> 16, j23 & 0xFFFFu, j23 >> 16);
    weights = vec4(unpackUnorm2x16(si_source[base + 7u]), unpackUnorm2x16(si_source[base + 8u]));
  }
  SiInstance inst = si_instances[u_chunk.w + i];
  vec4 m0, m1, m2;
  siSkin(inst, joints, weights, m0, m1, m2);
  vec4 w0 = inst.world_rows[0], w1 = inst.world_rows[1], w2 = inst.world_rows[2];
  vec3 world = siTransformPoint(w0, w1, w2, siTransformPoint(m0, m1, m2, p));
  vec3 normal = siTransformNormal(w0, w1, w2, siTransformNormal(m0, m1, m2, n));
  si_skinned_out[u_chunk.x + g] = vec4(world, uintBitsToFloat(packSnorm2x16(siOctEncode(normal))));
}
)";

const char* kPulledVertex = R"(
layout(std430, binding = 1) readonly buffer SiSkinned { vec4 si_skinned[]; };
layout(location = 1) uniform mat4 u_view_projection;
out vec3 v_normal;
out vec2 v_texcoord;
flat out uint v_color;
vec3 siOctDecode(vec2 e) {
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}
void main() {
  uint k = uint(gl_VertexID);
  vec4 s = si_skinned[u_chunk.x + uint(gl_InstanceID) * u_chunk.y + k];
  uint base = si_lod_vertices[u_chunk.z + k] * u_layout.y;
  v_texcoord = unpackHalf2x16(si_source[base + 4u]);
  v_normal = siOctDecode(unpackSnorm2x16(floatBitsToUint(s.w)));
  v_color = si_instances[u_chunk.w + uint(gl_InstanceID)].blend.w;
  gl_Position = u_view_projection * vec4(s.xyz, 1.0);
}
)";

struct ProgramResult {
  GLuint program = kNoObject;
  Status status;
};

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


}  // namespace

namespace detail {

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
    return {StatusCode::kBackend,
            strCat("compiling the ", name, " ",
                   type == GL_VERTEX_SHADER    ? "vertex"
                   : type == GL_COMPUTE_SHADER ? "compute"
                                               : "fragment",
                   " shader failed: ", log.c_str())};
  }
  *out = shader;
  return Status::ok();
}

// Checks a linked program: kBackend with the driver's log (and the program deleted) on failure.
Status finishLink(GLuint program, const char* name, GLuint* out) {
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
  return finishLink(program, name, out);
}

Status linkCompute(const std::string& cs, const char* name, GLuint* out) {
  GLuint c = kNoObject;
  Status s = compile(GL_COMPUTE_SHADER, cs, name, &c);
  if (!s.isOk()) return s;
  const GLuint program = glCreateProgram();
  glAttachShader(program, c);
  glLinkProgram(program);
  glDeleteShader(c);
  return finishLink(program, name, out);
}

}  // namespace detail


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
  GLuint compute_ids[2] = {kNoObject, kNoObject};
  if (s.isOk())
    s = linkCompute(header + include + kPreSkinDecl + kComputeSkin, "compute skinning",
                    &compute_ids[0]);
  if (s.isOk())
    s = link(header + include + kPreSkinDecl + kPulledVertex, kFragment, "pre-skinned pulling",
             nullptr, &compute_ids[1]);
  GLuint gpu_draw = kNoObject;
  if (s.isOk())
    s = link(header + "#define SI_GPU_DRIVEN\n" + include + kSkinnedMain, kFragment,
             "GPU-driven skinned", nullptr, &gpu_draw);
  impl->gpu.draw = describe(gpu_draw);
  if (s.isOk()) s = impl->createGpuCullPrograms(header);
  impl->compute_skin = describe(compute_ids[0]);
  impl->pulled = describe(compute_ids[1]);
  impl->path = desc.skinning_path == SkinningPath::kCompute ? SkinningPath::kCompute
                                                             : SkinningPath::kVertexShader;
  impl->path_reason = desc.skinning_path == SkinningPath::kAutomatic
                          ? "not measured yet (uploadCharacter measures)"
                          : "explicit setting";
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
                           &m.preskinned, &m.compute_skin, &m.pulled})
    if (p->id != kNoObject) glDeleteProgram(p->id);
  const GLuint compute_buffers[] = {m.pre_index_buffer, m.lod_vertex_list, m.skinned_ring};
  glDeleteBuffers(3, compute_buffers);
  if (m.pre_vao != kNoObject) glDeleteVertexArrays(1, &m.pre_vao);
  if (m.cpu_vao != kNoObject) glDeleteVertexArrays(1, &m.cpu_vao);
  if (m.cpu_stream != kNoObject) glDeleteBuffers(1, &m.cpu_stream);
  const GLuint buffers[] = {m.vertex_buffer, m.index_buffer, m.character_ubo};
  glDeleteBuffers(3, buffers);
  const GLuint textures[] = {m.palette_texture, m.base_texture};
  glDeleteTextures(2, textures);
  if (m.vao != kNoObject) glDeleteVertexArrays(1, &m.vao);
  if (m.timer != kNoObject) glDeleteQueries(1, &m.timer);
  m.releaseGpuCull();
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
  m.wide_joints = wide;
  glCreateVertexArrays(1, &m.vao);
  m.describeVertexFormat(m.vao);
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
  // Compute pre-skinning: the vertices each (sub-mesh, LOD) uses, compacted, and its triangles
  // re-indexed to them, so the compute pass skins exactly what is drawn.
  std::vector<uint32_t> lod_vertices, local_indices, local(mesh.vertexCount(), UINT32_MAX);
  m.pre_lods.assign(mesh.sub_meshes.size(), {});
  m.max_lod_vertices = 0;
  for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm)
    for (const IndexRange& r : mesh.sub_meshes[sm].lods) {
      Impl::PreLod pl;
      pl.first_index = uint32_t(local_indices.size());
      pl.index_count = r.index_count;
      pl.vertex_offset = uint32_t(lod_vertices.size());
      std::vector<uint32_t> used(mesh.indices.begin() + r.first_index,
                                 mesh.indices.begin() + r.first_index + r.index_count);
      std::sort(used.begin(), used.end());
      used.erase(std::unique(used.begin(), used.end()), used.end());
      for (size_t k = 0; k < used.size(); ++k) local[used[k]] = uint32_t(k);
      lod_vertices.insert(lod_vertices.end(), used.begin(), used.end());
      for (uint32_t i = r.first_index; i < r.first_index + r.index_count; ++i)
        local_indices.push_back(local[mesh.indices[i]]);
      pl.vertex_count = uint32_t(used.size());
      m.max_lod_vertices = std::max(m.max_lod_vertices, pl.vertex_count);
      m.pre_lods[sm].push_back(pl);
    }
  const GLuint old_pre[] = {m.pre_index_buffer, m.lod_vertex_list};
  glDeleteBuffers(2, old_pre);
  if (m.pre_vao != kNoObject) glDeleteVertexArrays(1, &m.pre_vao);
  lod_vertices.push_back(0);  // Never empty (a zero-sized buffer is an error).
  local_indices.push_back(0);
  glCreateBuffers(1, &m.lod_vertex_list);
  glNamedBufferStorage(m.lod_vertex_list, GLsizeiptr(lod_vertices.size() * 4), lod_vertices.data(), 0);
  glCreateBuffers(1, &m.pre_index_buffer);
  glNamedBufferStorage(m.pre_index_buffer, GLsizeiptr(local_indices.size() * 4),
                       local_indices.data(), 0);
  glCreateVertexArrays(1, &m.pre_vao);
  glVertexArrayElementBuffer(m.pre_vao, m.pre_index_buffer);
  m.source_words = uint32_t(stride / 4);
  if (m.skinned_ring != kNoObject &&
      m.skinned_ring_vertices < m.max_lod_vertices) {  // Regrow for a larger character.
    glDeleteBuffers(1, &m.skinned_ring);
    m.skinned_ring = kNoObject;
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
  s = m.check("uploadCharacter");
  if (s.isOk() && m.desc.skinning_path == SkinningPath::kAutomatic)
    s = m.measurePaths(light_direction_);
  return s;
}

// Times both skinning paths on a synthetic crowd of sub-mesh 0 at LOD 0 (about 2^20 vertices, a
// crowd-sized draw: smaller ones mislead on llvmpipe, whose vertex path slows superlinearly; clip
// 0 between two frames; the best of two after a warm-up) drawn into a small framebuffer of its own, and keeps the
// faster. The application's framebuffer and viewport are restored.
Status Renderer::Impl::measurePaths(const glm::vec3& light) {
  if (pre_lods.empty() || pre_lods[0].empty() || pre_lods[0][0].vertex_count == 0 ||
      palette == nullptr || palette->clips.empty()) {
    path = SkinningPath::kVertexShader;
    path_reason = "nothing to measure (empty mesh or palette): the vertex shader by default";
    return Status::ok();
  }
  const uint32_t nv = pre_lods[0][0].vertex_count;
  const uint32_t n = std::clamp<uint32_t>((1u << 20) / nv + 1, 1u, capacity * 16);
  const uint32_t batches = (n + capacity - 1) / capacity;
  const size_t block = (size_t(block_size) + alignment - 1) / alignment * alignment;
  Status s = ensureRing(block * batches);
  if (!s.isOk()) return s;
  const uint32_t r = ring_index;
  acquireRegion(r);
  const size_t base = size_t(r) * region_size;
  const BakedClip& clip = palette->clips[0];
  const uint32_t next = clip.first_texel + (clip.frame_count > 1 ? palette->layout.frame_stride_texels : 0);
  const float half = 0.5f;
  const uint32_t side = uint32_t(std::ceil(std::sqrt(double(n))));
  const float scale = 1.0f / float(side);
  draws.clear();
  for (uint32_t b = 0; b < batches; ++b) {
    DrawBatch d;
    d.byte_offset = uint32_t(b * block);
    d.instance_count = std::min(capacity, n - b * capacity);
    for (uint32_t i = 0; i < d.instance_count; ++i) {
      const uint32_t index = b * capacity + i;
      InstanceRecord rec{};
      // Clip space directly (identity camera): a grid of small characters filling the view.
      const float x = (float(index % side) + 0.5f) * 2.0f * scale - 1.0f;
      const float y = (float(index / side) + 0.1f) * 2.0f * scale - 1.0f;
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) rec.world_rows[row][col] = row == col ? scale * 0.45f : 0.0f;
      rec.world_rows[0][3] = x;
      rec.world_rows[1][3] = y;
      rec.world_rows[2][3] = 0.0f;
      rec.frames[0] = rec.frames[2] = clip.first_texel;
      rec.frames[1] = rec.frames[3] = next;
      std::memcpy(&rec.blend[0], &half, 4);
      std::memcpy(&rec.blend[1], &half, 4);
      rec.blend[3] = 0xFFFFFFFFu;
      std::memcpy(ring_mapped + base + d.byte_offset + size_t(i) * sizeof(rec), &rec, sizeof(rec));
    }
    draws.push_back(d);
  }
  // A framebuffer of its own.
  GLint previous_fbo = 0, viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_fbo);
  glGetIntegerv(GL_VIEWPORT, viewport);
  GLuint fbo = kNoObject, targets[2] = {kNoObject, kNoObject};
  glCreateFramebuffers(1, &fbo);
  glCreateRenderbuffers(2, targets);
  glNamedRenderbufferStorage(targets[0], GL_RGBA8, 256, 256);
  glNamedRenderbufferStorage(targets[1], GL_DEPTH_COMPONENT24, 256, 256);
  glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, targets[0]);
  glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, targets[1]);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
  glViewport(0, 0, 256, 256);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  const Camera identity;
  double best[2] = {1e30, 1e30};
  for (int rep = 0; rep < 3; ++rep)
    for (int p = 0; p < 2; ++p) {
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      glBeginQuery(GL_TIME_ELAPSED, timer);
      DrawStats st;
      if (p == 0) {
        bindCommon(skinned, identity, light);
        drawVertexPath(base, &st);
      } else {
        s = drawComputePath(identity, light, base, &st);
      }
      glEndQuery(GL_TIME_ELAPSED);
      GLuint64 ns = 0;
      glGetQueryObjectui64v(timer, GL_QUERY_RESULT, &ns);
      if (rep > 0) best[p] = std::min(best[p], double(ns) * 1e-6);  // Rep 0 warms up.
      if (!s.isOk()) break;
    }
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(previous_fbo));
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  glDeleteFramebuffers(1, &fbo);
  glDeleteRenderbuffers(2, targets);
  fences[r] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  ring_index = (r + 1) % ring_frames;
  if (!s.isOk()) return s;
  path = best[1] < best[0] ? SkinningPath::kCompute : SkinningPath::kVertexShader;
  char text[200];
  std::snprintf(text, sizeof text,
                "measured %u instances x %u vertices: vertex shader %.3f ms, compute %.3f ms",
                n, nv, best[0], best[1]);
  path_reason = text;
  logMessage(LogLevel::kInfo,
             strCat("si::Renderer: skinning path ", skinningPathName(path), " (", text, ")"));
  return check("measuring the skinning paths");
}

const char* skinningPathName(SkinningPath path) {
  switch (path) {
    case SkinningPath::kAutomatic: return "automatic";
    case SkinningPath::kVertexShader: return "vertex-shader";
    case SkinningPath::kCompute: return "compute";
  }
  return "unknown";
}

SkinningPath Renderer::skinningPath() const {
  return impl_ ? impl_->path : SkinningPath::kVertexShader;
}

const std::string& Renderer::skinningPathReason() const {
  static const std::string none = "no renderer (init() first)";
  return impl_ ? impl_->path_reason : none;
}

uint64_t Renderer::computeRingBytes() const {
  return impl_ && impl_->skinned_ring != kNoObject ? impl_->skinned_ring_vertices * 16 : 0;
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
  if (mode == DrawMode::kDefault)
    mode = m.path == SkinningPath::kCompute ? DrawMode::kComputeSkinned : DrawMode::kSkinned;
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  DrawStats st;
  if (mode == DrawMode::kComputeSkinned) {
    s = m.ensureSkinnedRing();
    if (!s.isOk()) return s;
    m.beginTimer(stats);
    s = m.drawComputePath(camera, light_direction_, base, &st);
    if (!s.isOk()) return s;
  } else {
    const Program& program = mode == DrawMode::kDepthOnly ? m.depth
                             : mode == DrawMode::kRigid   ? m.rigid
                                                          : m.skinned;
    m.bindCommon(program, camera, light_direction_);
    if (mode == DrawMode::kDepthOnly) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    m.beginTimer(stats);
    m.drawVertexPath(base, &st);
  }
  st.cpu_submit_ms = msSince(t0);  // Before the (blocking) timer read.
  st.gpu_ms = m.endTimer(stats);
  if (mode == DrawMode::kDepthOnly) glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  m.fences[r] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  m.ring_index = (r + 1) % m.ring_frames;
  s = m.check("drawCrowd");
  if (stats != nullptr) *stats = st;
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
  st.gpu_ms = m.endTimer(stats);
  Status s = m.check("drawTraditional");
  if (stats != nullptr) *stats = st;
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
  st.gpu_ms = m.endTimer(stats);
  Status s = m.check("drawCpuSkinned");
  if (stats != nullptr) *stats = st;
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
