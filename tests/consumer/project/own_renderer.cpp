// See own_renderer.h.
#include "own_renderer.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "si/core/shader_inputs.h"
#include "si/crowd/crowd_manager.h"

namespace consumer {

namespace {

// The engine's include resolver, reduced to what GLSL needs here: each `#include "x"` line of
// `text` replaced by x's text (from `dir`), recursively.
std::string resolveIncludes(const std::string& text, const std::string& dir, int depth = 0) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.compare(0, 10, "#include \"") != 0) {
      out += line + "\n";
      continue;
    }
    const std::string name = line.substr(10, line.find('"', 10) - 10);
    std::ifstream file(dir + "/" + name);
    std::ostringstream included;
    included << file.rdbuf();
    out += file && depth < 16 ? resolveIncludes(included.str(), dir, depth + 1)
                              : "#error cannot include " + name + "\n";
  }
  return out;
}

// The engine's shaders: skinning from the include, shading through the installed built-in
// material (si_surface.glsl's interface, builtin_material.glsl's glTF metallic-roughness) with
// the three library functions it calls defined here as si::Renderer defines them (the tint
// where the texture's alpha says so, the renderer's light, no motion).
const char* kVertexMain = R"(
#include "si_skinning.glsl"
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_normal;
layout(location = 2) in vec2 a_texcoord;
layout(location = 3) in uvec4 a_joints;
layout(location = 4) in vec4 a_weights;
layout(location = 1) uniform mat4 u_view_projection;
out vec3 v_position;  // Camera-relative, as the records are.
out vec3 v_normal;
out vec2 v_texcoord;
flat out uint v_color;
void main() {
  SiInstance inst = si_instances[gl_InstanceID];
  vec4 m0, m1, m2;
  siSkin(inst, a_joints, a_weights, m0, m1, m2);
  vec4 w0 = inst.world_rows[0], w1 = inst.world_rows[1], w2 = inst.world_rows[2];
  vec3 world = siTransformPoint(w0, w1, w2, siTransformPoint(m0, m1, m2, a_position));
  v_position = world;
  v_normal = siTransformNormal(w0, w1, w2, siTransformNormal(m0, m1, m2, a_normal.xyz));
  v_texcoord = a_texcoord;
  v_color = inst.blend.w;
  gl_Position = u_view_projection * vec4(world, 1.0);
}
)";
const char* kFragmentMain = R"(
#include "si_surface.glsl"
in vec3 v_position;
in vec3 v_normal;
in vec2 v_texcoord;
flat in uint v_color;
layout(binding = 1) uniform sampler2D u_base_color;  // sRGB: decoded as it is sampled.
layout(location = 2) uniform vec4 u_base_factor;
layout(location = 3) uniform vec3 u_light_direction;
layout(location = 4) uniform vec2 u_metallic_roughness;
vec3 siSurfaceAlbedo(SiSurface s) {
  return mix(s.base_color.rgb, s.base_color.rgb * s.tint, s.base_color.a);
}
vec2 siSurfaceMotion(SiSurface s) { return vec2(0.0); }
vec3 siLightDirection() { return u_light_direction; }
void siMaterial(SiSurface s);
void main() {
  SiSurface s;
  s.position = v_position;
  s.normal = normalize(v_normal);
  s.vertex_normal = s.normal;
  s.tangent = vec4(0.0);
  s.uv0 = v_texcoord;
  s.material = 0u;
  s.base_color = texture(u_base_color, v_texcoord) * u_base_factor;
  s.metallic = u_metallic_roughness.x;
  s.roughness = u_metallic_roughness.y;
  s.occlusion = 1.0;
  s.emissive = vec3(0.0);
  s.tint = unpackUnorm4x8(v_color).rgb;
  s.custom_layer = -1;
  s.lod = 0u;
  s.impostor = false;
  s.clip_position = vec4(0.0);
  s.previous_clip_position = vec4(0.0);
  siMaterial(s);
}
#include "builtin_material.glsl"
)";

std::string compile(GLenum type, const std::string& source, GLuint* out) {
  const GLuint s = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    return std::string("shader compile failed: ") + log;
  }
  *out = s;
  return "";
}

}  // namespace

std::string drawWithOwnRenderer(const std::string& glsl_dir,
                                const si::Character& character, const si::BakedPalette& palette,
                                const si::CrowdManager& crowd, const float view_projection[16],
                                const float light[3], const float clear_rgb[3],
                                uint32_t max_uniform_block_bytes,
                                uint32_t uniform_offset_alignment) {
  std::string error;

  // Batching for the engine's uniform block.
  si::InstanceBatcher batcher;
  si::BatchLimits limits;
  limits.max_uniform_block_size_bytes = max_uniform_block_bytes;
  limits.uniform_buffer_offset_alignment = uniform_offset_alignment;
  si::Status s = batcher.init(limits);
  if (!s.isOk()) return s.toString();
  const uint32_t capacity = batcher.capacityPerDraw();

  // Program: the include as installed, resolved by the engine.
  const std::string vs_text = resolveIncludes(
      "#version 450 core\n#define SI_MAX_INSTANCES " + std::to_string(capacity) +
          "\n#define SI_PALETTE_INFO_BINDING 7\n" + kVertexMain,
      glsl_dir);
  GLuint vs = 0, fs = 0;
  error = compile(GL_VERTEX_SHADER, vs_text, &vs);
  if (error.empty())
    error = compile(GL_FRAGMENT_SHADER,
                    resolveIncludes(std::string("#version 450 core\n") + kFragmentMain, glsl_dir),
                    &fs);
  if (!error.empty()) return error;
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) return "program link failed";

  // The character: the vertex stream the include expects, and the indices.
  si::VertexStream stream;
  s = si::buildVertexStream(character.mesh, palette, &stream);
  if (!s.isOk()) return s.toString();
  GLuint buffers[4] = {0, 0, 0, 0};  // vertices, indices, records, palette info
  glCreateBuffers(4, buffers);
  glNamedBufferStorage(buffers[0], GLsizeiptr(stream.bytes.size()), stream.bytes.data(), 0);
  glNamedBufferStorage(buffers[1], GLsizeiptr(character.mesh.indices.size() * 4),
                        character.mesh.indices.data(), 0);
  GLuint vao = 0;
  glCreateVertexArrays(1, &vao);
  glVertexArrayVertexBuffer(vao, 0, buffers[0], 0, GLsizei(stream.stride_bytes));
  glVertexArrayElementBuffer(vao, buffers[1]);
  for (GLuint loc = 0; loc < 5; ++loc) {
    glEnableVertexArrayAttrib(vao, loc);
    glVertexArrayAttribBinding(vao, loc, 0);
  }
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, si::VertexStream::kPositionOffset);
  glVertexArrayAttribFormat(vao, 1, 4, GL_INT_2_10_10_10_REV, GL_TRUE,
                             si::VertexStream::kNormalOffset);
  glVertexArrayAttribFormat(vao, 2, 2, GL_HALF_FLOAT, GL_FALSE, si::VertexStream::kTexcoordOffset);
  glVertexArrayAttribIFormat(vao, 3, 4, stream.wide_joints ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE,
                              si::VertexStream::kJointsOffset);
  glVertexArrayAttribFormat(vao, 4, 4, GL_UNSIGNED_SHORT, GL_TRUE, stream.weights_offset);

  // The palette (matrix formats in float32 here) and the base colour texture.
  GLuint textures[2] = {0, 0};
  glCreateTextures(GL_TEXTURE_2D, 2, textures);
  glTextureStorage2D(textures[0], 1, GL_RGBA32F, GLsizei(palette.layout.width),
                      GLsizei(palette.layout.height));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(textures[0], 0, 0, 0, GLsizei(palette.layout.width),
                       GLsizei(palette.layout.height), GL_RGBA, GL_FLOAT,
                       palette.texel_bytes.data());
  glTextureParameteri(textures[0], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(textures[0], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  const si::Material& material = character.materials.at(0);
  const si::Image& image = character.images.at(size_t(material.base_color_image));
  const GLsizei levels =
      GLsizei(std::floor(std::log2(double(std::max(image.width, image.height))))) + 1;
  glTextureStorage2D(textures[1], levels, GL_SRGB8_ALPHA8, GLsizei(image.width),
                     GLsizei(image.height));
  glTextureSubImage2D(textures[1], 0, 0, 0, GLsizei(image.width), GLsizei(image.height), GL_RGBA,
                       GL_UNSIGNED_BYTE, image.rgba8.data());
  glGenerateTextureMipmap(textures[1]);
  glTextureParameteri(textures[1], GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(textures[1], GL_TEXTURE_MAG_FILTER, GL_LINEAR);

  // The palette's info block (si::paletteShaderInfo) at the binding the engine chose for it
  // (SI_PALETTE_INFO_BINDING above), the camera and shading.
  const glm::uvec4 palette_info = si::paletteShaderInfo(palette);
  glNamedBufferStorage(buffers[3], sizeof(palette_info), &palette_info[0], 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, 7, buffers[3]);
  glProgramUniformMatrix4fv(program, 1, 1, GL_FALSE, view_projection);
  glProgramUniform4fv(program, 2, 1, &material.base_color_factor[0]);
  glProgramUniform3fv(program, 3, 1, light);
  glProgramUniform2f(program, 4, material.metallic_factor, material.roughness_factor);

  // The frame: records into the engine's buffer, then one instanced draw per batch.
  glClearColor(clear_rgb[0], clear_rgb[1], clear_rgb[2], 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const GLsizeiptr block_bytes = GLsizeiptr(capacity) * GLsizeiptr(si::kInstanceRecordSize);
  std::vector<uint8_t> records(batcher.recordBufferBound(crowd.view()) + size_t(block_bytes));
  std::vector<si::DrawBatch> draws;
  s = batcher.build(crowd.view(), records, &draws);
  if (!s.isOk()) return s.toString();
  glNamedBufferStorage(buffers[2], GLsizeiptr(records.size()), records.data(), 0);
  glUseProgram(program);
  glBindVertexArray(vao);
  glBindTextureUnit(0, textures[0]);
  glBindTextureUnit(1, textures[1]);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  for (const si::DrawBatch& d : draws) {
    const std::vector<si::IndexRange>& lods = character.mesh.sub_meshes[d.sub_mesh].lods;
    const si::IndexRange r = lods[std::min<size_t>(d.lod, lods.size() - 1)];
    glBindBufferRange(GL_UNIFORM_BUFFER, 0, buffers[2], GLintptr(d.byte_offset), block_bytes);
    glDrawElementsInstanced(GL_TRIANGLES, GLsizei(r.index_count), GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(uintptr_t(r.first_index) * 4),
                             GLsizei(d.instance_count));
  }
  const GLenum gl_error = glGetError();
  glDeleteProgram(program);
  glDeleteBuffers(4, buffers);
  glDeleteVertexArrays(1, &vao);
  glDeleteTextures(2, textures);
  return gl_error == GL_NO_ERROR ? "" : "GL error " + std::to_string(gl_error);
}

}  // namespace consumer
