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
  Status s = renderer.init(setup.info, rd);
  CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(setup.character, palette, &id);
  if (s.isOk()) s = addImpostor(setup, renderer, id);
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
      Row rows[2];  // The built-in material, then the host's.
      s = timePaired(setup, renderer, palette, count, path, [&](int k) {
        return renderer.setMaterial(id, k == 0 ? kBuiltinMaterial : host);
      }, rows);
      if (!s.isOk()) break;
      rows[0].lod = "builtin";
      rows[1].lod = "host";
      for (const Row& row : rows) {
        printSideBySideRow(row, rows[0], "materials", csv);
        std::printf("\n");
      }
      Row handle_rows[2];  // The host material, then the same reading the instance handle.
      s = timePaired(
          setup, renderer, palette, count, path,
          [&](int k) { return renderer.setMaterial(id, k == 0 ? host : host_handle); },
          handle_rows);
      if (!s.isOk()) break;
      handle_rows[0].lod = "host";
      handle_rows[1].lod = "host+handle";
      for (const Row& row : handle_rows) {
        printSideBySideRow(row, handle_rows[0], "materials", csv);
        std::printf("\n");
      }
    }
  (void)renderer.setMaterial(id, kBuiltinMaterial);
  glDeleteBuffers(1, &block);
  if (!s.isOk()) return {s.code(), "materials: " + s.message()};
  return Status::ok();
}

}  // namespace si::bench
