// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Build step of si::vk: writes the GLSL of the Vulkan back-end's programs, assembled from the
// same shader files and program catalog as si::gl's (src/gl/programs/program_catalog.h), one
// file per stage, for glslangValidator to compile to SPIR-V (src/vk/CMakeLists.txt).
// Usage: si_vk_write_glsl <output folder> <program name>...: the names the build expects, which
// must be vulkanPrograms()' in order (so the two lists cannot drift apart).
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <string>

#include "vk/vulkan_programs.h"

int main(int argc, char** argv) {
  const auto programs = si::vk::detail::vulkanPrograms();
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s <output folder> <program name>...\n", argv[0]);
    return 2;
  }
  bool same = size_t(argc - 2) == programs.size();
  for (size_t k = 0; same && k < programs.size(); ++k) same = programs[k].name == argv[2 + k];
  if (!same) {
    std::fprintf(stderr, "%s: the build names other programs than vulkanPrograms():", argv[0]);
    for (const auto& p : programs) std::fprintf(stderr, " %s", p.name.c_str());
    std::fprintf(stderr, "\n");
    return 1;
  }
  using si::detail::ShaderStage;
  for (const si::vk::detail::VulkanProgram& p : programs) {
    const std::initializer_list<ShaderStage> graphics = {ShaderStage::kVertex,
                                                         ShaderStage::kFragment};
    const std::initializer_list<ShaderStage> compute = {ShaderStage::kCompute};
    for (ShaderStage stage : p.compute ? compute : graphics) {
      std::string source;
      const si::Status s =
          si::detail::assembleStage(p.id, stage, si::vk::detail::vulkanShaderConfig(p), &source);
      if (!s.isOk()) {
        std::fprintf(stderr, "%s: %s\n", p.name.c_str(), s.toString().c_str());
        return 1;
      }
      const std::string path = std::string(argv[1]) + "/" + p.name + "." +
                               (stage == ShaderStage::kVertex     ? "vert"
                                : stage == ShaderStage::kFragment ? "frag"
                                                                  : "comp");
      std::ofstream out(path, std::ios::binary);
      out << source;
      if (!out) {
        std::fprintf(stderr, "cannot write %s\n", path.c_str());
        return 1;
      }
    }
  }
  return 0;
}
