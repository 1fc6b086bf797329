// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/materials_table.h"

#include <glad/gl.h>

#include "crowd_bench/bench_character.h"

namespace si::bench {

namespace {

// The built-in material's arithmetic (shaders/builtin_material.glsl) with the light read from
// the host's uniform block at binding 7: the cost of the material stage itself.
constexpr const char* kHostLambert = R"(
layout(location = 0) out vec4 o_color;
layout(std140, binding = 7) uniform HostLight { vec4 host_direction; };
void siMaterial(SiSurface s) {
  float lambert = max(dot(s.normal, -host_direction.xyz), 0.0);
  o_color = vec4(siSurfaceAlbedo(s) * (0.35 + 0.65 * lambert), 1.0);
})";

// The same, asking for the instance handle (MaterialDesc::instance_handle) and reading it: the
// cost of handing the handle over.
constexpr const char* kHostLambertHandle = R"(
layout(location = 0) out vec4 o_color;
layout(std140, binding = 7) uniform HostLight { vec4 host_direction; };
void siMaterial(SiSurface s) {
  float lambert = max(dot(s.normal, -host_direction.xyz), 0.0);
  o_color = vec4(siSurfaceAlbedo(s) * (0.35 + 0.65 * lambert), s.instance != 0u ? 1.0 : 0.0);
})";

}  // namespace

Status materialsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                      const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                      std::FILE* csv) {
  RendererDesc rd = desc;
  rd.skinning_path = SkinningPath::kVertexShader;  // Each path names its draw mode.
  Renderer renderer;
  Status s = initRenderer(setup, palette, rd, &renderer);
  const CharacterId id{};  // initRenderer's character.
  MaterialDesc md;
  md.name = "host lambert";
  md.source = kHostLambert;
  MaterialId host, host_handle;
  const auto compile_start = Clock::now();
  if (s.isOk()) s = renderer.addMaterial(md, &host);
  const double compile_ms = msSince(compile_start);
  md.name = "host lambert with the instance handle";
  md.source = kHostLambertHandle;
  md.instance_handle = true;
  if (s.isOk()) s = renderer.addMaterial(md, &host_handle);
  if (!s.isOk()) return {s.code(), "materials: " + s.message()};
  // The host's light: the renderer's default direction, bound where the material reads it.
  const glm::vec4 light(glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f)), 0.0f);
  GLuint block = 0;
  glCreateBuffers(1, &block);
  glNamedBufferStorage(block, sizeof(light), &light, 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, 7, block);
  std::printf(
      "\nMaterials: each frame of the field drawn with the built-in material, then with "
      "a host material computing the library's former look (Lambert over a constant ambient) "
      "from its own uniform block, by the same renderer; then the host material against "
      "the same asking for the instance handle (host+handle); medians over the frames "
      "(addMaterial compiled its programs in %.0f ms)\n",
      compile_ms);
  printSideBySideHeader("material");
  std::printf("\n");
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      // Two pairs: the built-in material against the host's, then the host's against the same
      // reading the instance handle; each row against its pair's first.
      const MaterialId pairs[2][2] = {{kBuiltinMaterial, host}, {host, host_handle}};
      const char* names[2][2] = {{"builtin", "host"}, {"host", "host+handle"}};
      for (int p = 0; p < 2 && s.isOk(); ++p) {
        Row rows[2];
        s = timePaired(
            setup, renderer, palette, count, path,
            [&](int k) { return renderer.setMaterial(id, pairs[p][k]); }, rows);
        for (int k = 0; k < 2 && s.isOk(); ++k) {
          rows[k].lod = names[p][k];
          printSideBySideRow(rows[k], rows[0], "materials", csv);
          std::printf("\n");
        }
      }
      if (!s.isOk()) break;
    }
  (void)renderer.setMaterial(id, kBuiltinMaterial);
  glDeleteBuffers(1, &block);
  if (!s.isOk()) return {s.code(), "materials: " + s.message()};
  return Status::ok();
}

}  // namespace si::bench
