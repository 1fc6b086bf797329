// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The Vulkan back-end's SPIR-V (issue "The crowd in a Vulkan engine", "the same shaders"),
// without a GPU: every program's stages are embedded and valid for Vulkan 1.3 (spirv-val), what
// the reader finds in each module is what glslang itself reports compiling the same GLSL, and
// the stages of a program agree on every binding, within the profile's ranges.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "si_vk/vulkan_profile.h"
#include "vk/spirv_modules.h"
#include "vk/spirv_reflect.h"
#include "vk/vulkan_programs.h"

#ifndef SI_VK_GLSL_DIR
#error "SI_VK_GLSL_DIR must name the build's assembled Vulkan GLSL"
#endif

namespace si::vk::detail {
namespace {

bool have(const char* tool) {
  return std::system((std::string(tool) + " --version >/dev/null 2>&1").c_str()) == 0;
}

void skipWithout(const char* tool, const char* package) {
  if (have(tool)) return;
  if (std::getenv("SI_REQUIRE_GLSLANG") != nullptr)
    FAIL() << tool << " not found (install " << package << ": scripts/deps.sh)";
  GTEST_SKIP() << tool << " not found (Debian package " << package << ")";
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A program's stages: a vertex and a fragment stage, or a compute stage alone.
std::vector<const char*> stagesOf(const VulkanProgram& p) {
  if (p.compute) return {"comp"};
  return {"vert", "frag"};
}

// Each module's name: "<program>.<stage>".
std::vector<std::string> moduleNames() {
  std::vector<std::string> names;
  for (const VulkanProgram& p : vulkanPrograms())
    for (const char* stage : stagesOf(p)) names.push_back(std::string(p.name) + "." + stage);
  return names;
}

// The binding of a stage's default uniform block, by the module's name.
uint32_t defaultsBindingOf(const std::string& module) {
  return module.find(".vert") != std::string::npos   ? kVertexDefaultsBinding
         : module.find(".comp") != std::string::npos ? kComputeDefaultsBinding
                                                     : kFragmentDefaultsBinding;
}

TEST(VulkanSpirv, EveryProgramsStagesAreEmbeddedAndValidForVulkan13) {
  skipWithout("spirv-val", "spirv-tools");
  ASSERT_EQ(kSpirvModuleCount, moduleNames().size());
  size_t compute = 0;
  for (const VulkanProgram& p : vulkanPrograms()) compute += p.compute;
  EXPECT_EQ(compute, 38u) << "the GPU-driven path's cull, commands and scatter passes, 24 "
                             "pre-skinning variants (with and without the previous positions; "
                             "without layers, with layers and with composed layers), 4 layer "
                             "compose passes, 3 depth pyramid passes, the impostor quads pass, "
                             "the impostor atlas's 2 coverage passes and its resolve pass";
  for (const std::string& name : moduleNames()) {
    SCOPED_TRACE(name);
    const SpirvModule* m = findSpirvModule(name.c_str());
    ASSERT_NE(m, nullptr);
    const std::string file = ::testing::TempDir() + "si_vk_" + name + ".spv";
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(m->words), std::streamsize(m->word_count * 4));
    const std::string log = file + ".log";
    const int rc = std::system(
        ("spirv-val --target-env vulkan1.3 '" + file + "' >'" + log + "' 2>&1").c_str());
    EXPECT_EQ(rc, 0) << readFile(log);
  }
  EXPECT_EQ(findSpirvModule("no_such.vert"), nullptr);
}

// glslang's reflection (-q) of the GLSL the build compiled, with the build's options: each
// block's and sampler's binding, and each default-block member's offset and array stride.
struct GlslangReflection {
  std::map<std::string, int> bindings;  // Block (type) names and sampler names.
  std::map<std::string, int> defaults;  // Default-block member -> offset.
  std::map<std::string, int> strides;   // Default-block array member -> its array stride.
};

GlslangReflection glslangReflection(const std::string& name, uint32_t defaults_binding) {
  GlslangReflection r;
  const std::string log = ::testing::TempDir() + "si_vk_reflect_" + name + ".txt";
  const std::string command = std::string("glslangValidator ") + SI_VK_GLSLANG_OPTIONS +
                              " --sdub " + kDefaultUniformBlock + " 0 " +
                              std::to_string(defaults_binding) + " -q -o /dev/null '" +
                              SI_VK_GLSL_DIR + "/" + name + "' >'" + log + "' 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << readFile(log);
  std::istringstream in(readFile(log));
  std::string line, section;
  std::map<int, std::string> block_of_index;
  std::vector<std::pair<std::string, std::pair<int, int>>> members;  // name, (index, offset).
  std::map<std::string, int> member_strides;
  int block_index = 0;
  // "name: offset O, type T, size S, index I, binding B, ...".
  const auto field = [](const std::string& text, const char* key, int* value) {
    const size_t at = text.find(key);
    if (at == std::string::npos) return false;
    *value = std::atoi(text.c_str() + at + std::strlen(key));
    return true;
  };
  while (std::getline(in, line)) {
    if (line.find("reflection:") != std::string::npos) {
      section = line;
      continue;
    }
    const size_t colon = line.find(": offset ");
    int offset = 0, index = 0, binding = 0;
    if (colon == std::string::npos || !field(line, ": offset ", &offset) ||
        !field(line, ", index ", &index) || !field(line, ", binding ", &binding))
      continue;
    const std::string n = line.substr(0, colon);
    if (section.rfind("Uniform block reflection", 0) == 0 ||
        section.rfind("Buffer block reflection", 0) == 0) {
      r.bindings[n] = binding;
      block_of_index[block_index++] = n;
    } else if (section.rfind("Uniform reflection", 0) == 0) {
      if (binding >= 0)
        r.bindings[n] = binding;  // A sampler.
      else
        members.push_back({n, {index, offset}});
      int stride = 0;
      if (field(line, ", arrayStride ", &stride)) member_strides[n] = stride;
    }
  }
  for (const auto& [n, at] : members)
    if (block_of_index[at.first] == kDefaultUniformBlock) {
      r.defaults[n] = at.second;
      if (member_strides.count(n) != 0) r.strides[n] = member_strides[n];
    }
  return r;
}

TEST(VulkanSpirv, WhatTheReaderFindsIsWhatGlslangReports) {
  skipWithout("glslangValidator", "glslang-tools");
  size_t with_descriptors = 0;
  for (const std::string& name : moduleNames()) {
    SCOPED_TRACE(name);
    const bool vertex = name.find(".vert") != std::string::npos;
    const SpirvModule* m = findSpirvModule(name.c_str());
    ASSERT_NE(m, nullptr);
    SpirvReflection mine;
    const Status s =
        reflectSpirv(Span<const uint32_t>(m->words, m->word_count), kDefaultUniformBlock, &mine);
    ASSERT_TRUE(s.isOk()) << s.toString();
    const GlslangReflection theirs = glslangReflection(name, defaultsBindingOf(name));
    with_descriptors += theirs.bindings.empty() ? 0 : 1;
    EXPECT_EQ(mine.descriptors.size(), theirs.bindings.size());
    for (const SpirvDescriptor& d : mine.descriptors) {
      SCOPED_TRACE(d.name);
      EXPECT_EQ(d.set, 0u);
      const auto it = theirs.bindings.find(d.name);
      ASSERT_NE(it, theirs.bindings.end()) << "glslang does not name it";
      EXPECT_EQ(int(d.binding), it->second);
    }
    std::map<std::string, int> defaults, strides;
    for (const SpirvMember& member : mine.default_uniforms) {
      defaults[member.name] = int(member.offset);
      if (member.array_stride != 0) strides[member.name] = int(member.array_stride);
    }
    // Every member glslang reflects (those the stage reads) at its offset and stride; the
    // reader also lists the block's members no instruction reads (the pre-skinned draws'
    // u_chunk), which keep their place in the block.
    for (const auto& [member, offset] : theirs.defaults) {
      SCOPED_TRACE(member);
      ASSERT_EQ(defaults.count(member), 1u) << "the reader does not find it";
      EXPECT_EQ(defaults[member], offset);
      EXPECT_EQ(strides.count(member) != 0 ? strides[member] : 0,
                theirs.strides.count(member) != 0 ? theirs.strides.at(member) : 0);
    }
    if (vertex) {
      EXPECT_EQ(defaults.count("u_view_projection"), 1u) << "a vertex stage's camera";
    }
    if (name == "cull.comp") {  // std140 arrays of scalars: 16 bytes an element.
      EXPECT_EQ(strides["u_lines"], 16) << "the LOD lines";
    }
  }
  // Only the depth-only programs' fragment stages (empty) declare nothing; the impostors'
  // depth-only stage tests the atlas's coverage.
  size_t depth_only = 0;
  for (const VulkanProgram& p : vulkanPrograms())
    depth_only += p.kind == VulkanKind::kDepthOnly && !p.impostor;
  EXPECT_GT(depth_only, 0u);
  EXPECT_EQ(with_descriptors, moduleNames().size() - depth_only);
}

// The two stages of a program share one pipeline layout: a binding both declare is of one kind,
// and each kind keeps to its range of the profile (uniform blocks below the storage shift,
// storage blocks below the sampler shift, samplers below the image shift, images below the
// default blocks).
TEST(VulkanSpirv, TheStagesOfAProgramAgreeOnEveryBinding) {
  for (const VulkanProgram& p : vulkanPrograms()) {
    SCOPED_TRACE(p.name);
    std::map<uint32_t, DescriptorKind> kinds;
    for (const char* stage : stagesOf(p)) {
      const SpirvModule* m = findSpirvModule((std::string(p.name) + "." + stage).c_str());
      ASSERT_NE(m, nullptr);
      SpirvReflection r;
      ASSERT_TRUE(
          reflectSpirv(Span<const uint32_t>(m->words, m->word_count), kDefaultUniformBlock, &r)
              .isOk());
      for (const SpirvDescriptor& d : r.descriptors) {
        SCOPED_TRACE(d.name);
        const auto [it, added] = kinds.emplace(d.binding, d.kind);
        EXPECT_TRUE(added || it->second == d.kind)
            << "binding " << d.binding << " is a " << descriptorKindName(it->second) << " and a "
            << descriptorKindName(d.kind);
        if (d.name == kDefaultUniformBlock) {
          EXPECT_EQ(d.binding, defaultsBindingOf(std::string(".") + stage));
        } else if (d.kind == DescriptorKind::kUniformBuffer) {
          EXPECT_LT(d.binding, kStorageBindingShift);
        } else if (d.kind == DescriptorKind::kStorageBuffer) {
          EXPECT_GE(d.binding, kStorageBindingShift);
          EXPECT_LT(d.binding, kSamplerBindingShift);
        } else if (d.kind == DescriptorKind::kStorageImage) {
          EXPECT_GE(d.binding, kImageBindingShift);
          EXPECT_LT(d.binding, kVertexDefaultsBinding);
        } else {
          EXPECT_GE(d.binding, kSamplerBindingShift);
          EXPECT_LT(d.binding, kImageBindingShift);
        }
      }
    }
  }
}

// Vulkan joins a program's stages by location, not by name: every input of the fragment stage
// is an output of the vertex stage of the same name at the same location (si_profile.glsl's
// SI_VARYING_LAYOUT). Without it, skinned_motion's fragment stage read its motion inputs at 0 and
// 1, where the vertex stage wrote the position and normal.
TEST(VulkanSpirv, TheStagesOfAProgramMeetAtTheSameLocations) {
  for (const VulkanProgram& p : vulkanPrograms()) {
    SCOPED_TRACE(p.name);
    if (p.compute) continue;  // One stage.
    SpirvReflection stages[2];
    for (int k = 0; k < 2; ++k) {
      const SpirvModule* m =
          findSpirvModule((std::string(p.name) + (k == 0 ? ".vert" : ".frag")).c_str());
      ASSERT_NE(m, nullptr);
      ASSERT_TRUE(reflectSpirv(Span<const uint32_t>(m->words, m->word_count), kDefaultUniformBlock,
                               &stages[k])
                      .isOk());
    }
    std::map<std::string, uint32_t> written;
    for (const SpirvVarying& v : stages[0].outputs) written[v.name] = v.location;
    for (const SpirvVarying& v : stages[1].inputs) {
      SCOPED_TRACE(v.name);
      const auto it = written.find(v.name);
      ASSERT_NE(it, written.end()) << "the vertex stage does not write it";
      EXPECT_EQ(it->second, v.location);
    }
    if (std::string(p.name) == "skinned") {
      EXPECT_GE(stages[1].inputs.size(), 7u);
    }
  }
}

}  // namespace
}  // namespace si::vk::detail
