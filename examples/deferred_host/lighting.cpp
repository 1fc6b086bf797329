// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The deferred lighting pass.
#include "deferred_host/lighting.h"

#include <glad/gl.h>

#include <algorithm>

#include "deferred_host/gl_program.h"

namespace deferred {

namespace {

constexpr GLuint kLightBinding = 7;  // The host's own uniform binding (the library's are 0-4).

constexpr const char* kVertex = R"(#version 450 core
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

constexpr const char* kFragment = R"(#version 450 core
layout(binding = 0) uniform sampler2D u_albedo;
layout(binding = 1) uniform sampler2D u_normal;
layout(binding = 2) uniform sampler2D u_material;
layout(binding = 3) uniform sampler2D u_depth;
layout(location = 0) uniform mat4 u_clip_to_relative;  // Camera-relative position from NDC.
layout(location = 1) uniform int u_light_count;
layout(location = 2) uniform vec2 u_size;
struct Light { vec4 position_radius; vec4 colour; };  // Camera-relative position.
layout(std140, binding = 7) uniform Lights { Light lights[256]; };
layout(location = 0) out vec4 o_colour;
const float kPi = 3.14159265;
vec3 brdf(vec3 n, vec3 v, vec3 l, vec3 albedo, float metallic, float roughness) {
  vec3 h = normalize(l + v);
  float nl = max(dot(n, l), 0.0), nv = max(dot(n, v), 1e-4), nh = max(dot(n, h), 0.0);
  float a = roughness * roughness, a2 = a * a;
  float d = a2 / (kPi * pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
  float k = a * 0.5;
  float g = nl / (nl * (1.0 - k) + k) * nv / (nv * (1.0 - k) + k);
  vec3 f0 = mix(vec3(0.04), albedo, metallic);
  vec3 f = f0 + (1.0 - f0) * pow(1.0 - max(dot(h, v), 0.0), 5.0);
  vec3 specular = d * g * f / max(4.0 * nl * nv, 1e-4);
  vec3 diffuse = (1.0 - f) * (1.0 - metallic) * albedo / kPi;
  return (diffuse + specular) * nl;
}
void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  vec4 normal_kind = texelFetch(u_normal, texel, 0);
  if (normal_kind.a == 0.0) {  // Nothing drawn: the night sky.
    o_colour = vec4(0.02, 0.025, 0.04, 1.0);
    return;
  }
  vec4 albedo = texelFetch(u_albedo, texel, 0);
  vec2 mr = texelFetch(u_material, texel, 0).rg;
  float depth = texelFetch(u_depth, texel, 0).r;
  vec4 h = u_clip_to_relative * vec4(gl_FragCoord.xy / u_size * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
  vec3 p = h.xyz / h.w;
  vec3 n = normalize(normal_kind.xyz), v = normalize(-p);
  vec3 radiance = albedo.rgb * albedo.a * vec3(0.03, 0.035, 0.05);  // Sky, by the occlusion.
  for (int i = 0; i < u_light_count; ++i) {
    vec3 to = lights[i].position_radius.xyz - p;
    float d2 = dot(to, to), r = lights[i].position_radius.w;
    float window = clamp(1.0 - d2 * d2 / (r * r * r * r), 0.0, 1.0);
    if (window == 0.0) continue;
    vec3 l = to * inversesqrt(d2);
    radiance += lights[i].colour.rgb * window * window / (d2 + 1.0) *
                brdf(n, v, l, albedo.rgb, mr.r, max(mr.g, 0.05));
  }
  vec3 mapped = radiance / (1.0 + radiance);  // Reinhard.
  o_colour = vec4(pow(mapped, vec3(1.0 / 2.2)), 1.0);
}
)";

}  // namespace

si::Status LightingPass::init() {
  glCreateBuffers(1, &lights_);
  glNamedBufferStorage(lights_, GLsizeiptr(kMaxLights) * 32, nullptr, GL_DYNAMIC_STORAGE_BIT);
  glCreateVertexArrays(1, &vao_);
  return linkProgram("deferred lighting", kVertex, kFragment, &program_);
}

void LightingPass::release() {
  glDeleteProgram(program_);
  glDeleteBuffers(1, &lights_);
  glDeleteVertexArrays(1, &vao_);
  *this = LightingPass();
}

void LightingPass::draw(const GBuffer& gbuffer, const si::Camera& camera,
                        const std::vector<PointLight>& lights) const {
  const size_t count = std::min<size_t>(lights.size(), kMaxLights);
  std::vector<glm::vec4> block(count * 2);
  for (size_t i = 0; i < count; ++i) {
    block[i * 2] = glm::vec4(glm::vec3(lights[i].position - camera.position), lights[i].radius);
    block[i * 2 + 1] = glm::vec4(lights[i].colour, 0.0f);
  }
  if (count > 0) glNamedBufferSubData(lights_, 0, GLsizeiptr(block.size() * 16), block.data());
  const glm::mat4 inverse = glm::inverse(camera.projection * camera.view_rotation);
  glUseProgram(program_);
  glProgramUniformMatrix4fv(program_, 0, 1, GL_FALSE, &inverse[0][0]);
  glProgramUniform1i(program_, 1, GLint(count));
  glProgramUniform2f(program_, 2, float(gbuffer.width()), float(gbuffer.height()));
  glBindBufferBase(GL_UNIFORM_BUFFER, kLightBinding, lights_);
  const GLuint textures[4] = {gbuffer.texture(0), gbuffer.texture(1), gbuffer.texture(2),
                              gbuffer.depthTexture()};
  glBindTextures(0, 4, textures);
  glDisable(GL_DEPTH_TEST);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace deferred
