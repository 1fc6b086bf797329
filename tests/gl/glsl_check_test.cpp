// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The shaders checked without a GPU: every program of the catalog, assembled exactly as
// Renderer::init() assembles it (for a 64 KiB and a 16 KiB uniform block), is compiled by
// glslang's reference front-end (glslangValidator, Debian's glslang-tools); so is a user shader
// built on the public include, both ways it can be read. The embedded include must equal the
// source files with their includes resolved. Without glslangValidator the compile tests skip,
// unless SI_REQUIRE_GLSLANG is set (scripts/test.sh sets it in CI).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "gl/programs/program_catalog.h"
#include "si/gl/skinning_glsl.h"

#ifndef SI_GLSL_DIR
#error "SI_GLSL_DIR must name src/gl/shaders"
#endif

namespace si {
namespace {

using detail::ProgramId;
using detail::ShaderStage;

bool haveGlslang() { return std::system("glslangValidator --version >/dev/null 2>&1") == 0; }

void skipWithoutGlslang() {
  if (haveGlslang()) return;
  if (std::getenv("SI_REQUIRE_GLSLANG") != nullptr)
    FAIL() << "glslangValidator not found (install glslang-tools: scripts/deps.sh)";
  GTEST_SKIP() << "glslangValidator not found (Debian package glslang-tools)";
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Compiles `source` as `stage` ("vert", "frag", "comp") with glslang (OpenGL GLSL semantics,
// or glslang's `options`); returns "" on success, else glslang's output.
std::string compileWithGlslang(const std::string& source, const std::string& stage,
                               const std::string& name, const std::string& options = "") {
  const std::string dir = ::testing::TempDir();
  const std::string file = dir + "si_glsl_" + name + "." + stage;
  const std::string log = file + ".log";
  std::ofstream(file, std::ios::binary) << source;
  const std::string command =
      "glslangValidator " + options + " -S " + stage + " '" + file + "' >'" + log + "' 2>&1";
  if (std::system(command.c_str()) == 0) return "";
  return "glslangValidator failed on " + file + ":\n" + readFile(log);
}

const char* stageExtension(ShaderStage s) {
  return s == ShaderStage::kVertex ? "vert" : s == ShaderStage::kFragment ? "frag" : "comp";
}

// A file name for program `id`'s stage: its catalog name, spaces as underscores.
std::string fileName(ProgramId id, const std::string& prefix, const std::string& suffix) {
  std::string name = prefix + detail::programSpec(id).name + suffix;
  for (char& c : name)
    if (c == ' ') c = '_';
  return name;
}

// Calls `visit(id, stage)` for every stage every program of the catalog has.
template <typename Visit>
void forEachStage(const Visit& visit) {
  for (size_t p = 0; p < detail::kProgramCount; ++p)
    for (ShaderStage stage : {ShaderStage::kVertex, ShaderStage::kFragment, ShaderStage::kCompute})
      if (detail::programSpec(ProgramId(p)).file(stage) != nullptr) visit(ProgramId(p), stage);
}

// The defines of a renderer with blocks of `max_instances` records and 1024 joints.
detail::ShaderConfig checkConfig(uint32_t max_instances) {
  detail::ShaderConfig config;
  config.max_instances = max_instances;
  config.max_joints = 1024;
  return config;
}

TEST(GlslCheck, EveryProgramCompilesWithGlslang) {
  skipWithoutGlslang();
  int compiled = 0;
  for (uint32_t max_instances : {819u, 204u}) {
    const detail::ShaderConfig config = checkConfig(max_instances);
    forEachStage([&](ProgramId id, ShaderStage stage) {
      std::string source;
      ASSERT_TRUE(detail::assembleStage(id, stage, config, &source).isOk());
      EXPECT_EQ(compileWithGlslang(source, stageExtension(stage),
                                   fileName(id, "", "_" + std::to_string(max_instances))),
                "");
      ++compiled;
    });
  }
  // The catalog's 63 programs: 36 with a vertex and a fragment stage, 27 compute: 99 stages.
  EXPECT_EQ(compiled, 2 * 99);
}

// The same programs compile to SPIR-V for Vulkan under glslang's relaxed rules (-R: loose
// uniforms in a default block, gl_VertexID and gl_InstanceID), their bindings and locations
// mapped where they have none: the sources a Vulkan back-end would compile (issue "The crowd
// in a Vulkan engine", "the same shaders"), kept from drifting away from it.
TEST(GlslCheck, EveryProgramCompilesToSpirvForVulkan) {
  skipWithoutGlslang();
  const detail::ShaderConfig config = checkConfig(819);
  int compiled = 0;
  forEachStage([&](ProgramId id, ShaderStage stage) {
    std::string source;
    ASSERT_TRUE(detail::assembleStage(id, stage, config, &source).isOk());
    const std::string spv =
        ::testing::TempDir() +
        fileName(id, "si_spirv_", std::string("_") + stageExtension(stage) + ".spv");
    EXPECT_EQ(compileWithGlslang(source, stageExtension(stage), fileName(id, "vulkan_", ""),
                                 "-V -R --auto-map-bindings --auto-map-locations -o '" + spv + "'"),
              "");
    ++compiled;
  });
  EXPECT_EQ(compiled, 99);
}

// The variants for meshes with texture coordinates 1 or colours (SI_VERTEX_WORDS): every
// program that hands a mesh's surface to a material, both stages.
TEST(GlslCheck, TheVertexWordsVariantsCompileWithGlslang) {
  skipWithoutGlslang();
  detail::ShaderConfig config = checkConfig(819);
  config.vertex_words = true;
  int programs = 0;
  for (size_t p = 0; p < detail::kProgramCount; ++p) {
    const ProgramId id = ProgramId(p);
    if (!detail::readsVertexWords(id)) continue;
    ++programs;
    for (ShaderStage stage : {ShaderStage::kVertex, ShaderStage::kFragment}) {
      std::string source;
      ASSERT_TRUE(detail::assembleStage(id, stage, config, &source).isOk());
      EXPECT_NE(source.find("#define SI_VERTEX_WORDS\n"), std::string::npos);
      EXPECT_EQ(compileWithGlslang(source, stageExtension(stage), fileName(id, "", "_words")), "");
    }
  }
  // Every mesh colour program (surface.frag.glsl): the 23 shaded ones (the 25 that take a
  // material less the two impostor programs) and the impostor capture.
  EXPECT_EQ(programs, 24);
}

// Every program that skins a mesh's vertices (and with `composing` the layer compose passes),
// every stage it has, assembled with `config`: each holds `define` and compiles (files named
// with `suffix`); more than 20 programs.
void expectSkinningVariantsCompile(const detail::ShaderConfig& config, const std::string& define,
                                   const std::string& suffix, bool composing = false) {
  int programs = 0;
  for (size_t p = 0; p < detail::kProgramCount; ++p) {
    const ProgramId id = ProgramId(p);
    if (!detail::skinsVertices(id) && !(composing && detail::composesLayers(id))) continue;
    ++programs;
    const bool compute = detail::programSpec(id).compute != nullptr;
    for (ShaderStage stage :
         compute ? std::vector<ShaderStage>{ShaderStage::kCompute}
                 : std::vector<ShaderStage>{ShaderStage::kVertex, ShaderStage::kFragment}) {
      std::string source;
      ASSERT_TRUE(detail::assembleStage(id, stage, config, &source).isOk());
      EXPECT_NE(source.find("#define " + define + "\n"), std::string::npos);
      EXPECT_EQ(compileWithGlslang(source, stageExtension(stage), fileName(id, "", suffix)), "");
    }
  }
  EXPECT_GT(programs, 20);
}

// The variants for meshes with 8 influences (SI_EIGHT_INFLUENCES), with the vertex words too
// (a mesh may have both).
TEST(GlslCheck, TheEightInfluenceVariantsCompileWithGlslang) {
  skipWithoutGlslang();
  detail::ShaderConfig config = checkConfig(819);
  config.eight_influences = true;
  config.vertex_words = true;
  expectSkinningVariantsCompile(config, "SI_EIGHT_INFLUENCES", "_eight");
}

// The variants for meshes with morph targets (SI_MORPH_TARGETS), with 8 influences and the
// vertex words too (a mesh may have all three), and the layer compose passes' (they compose the
// overlays' morph weights).
TEST(GlslCheck, TheMorphTargetVariantsCompileWithGlslang) {
  skipWithoutGlslang();
  detail::ShaderConfig config = checkConfig(819);
  config.morph_targets = true;
  config.eight_influences = true;
  config.vertex_words = true;
  expectSkinningVariantsCompile(config, "SI_MORPH_TARGETS", "_morph", true);
}

// A G-buffer material like docs/rendering.md's ("Materials"): two targets, a uniform block of
// its own, a discard (so the depth-only programs take it too).
constexpr const char* kGbufferMaterial = R"(
layout(location = 0) out vec4 o_albedo;
layout(location = 1) out vec4 o_normal;
layout(std140, binding = 7) uniform Tone { vec4 tone; };
void siMaterial(SiSurface s) {
  if (s.base_color.a < 0.01 && !s.impostor) discard;
  o_albedo = vec4(siSurfaceAlbedo(s) * tone.rgb, 1.0);
  o_normal = vec4(s.normal * 0.5 + 0.5, float(s.lod) / 8.0);
#ifdef SI_MOTION_VECTORS
  o_normal.a = length(siSurfaceMotion(s));
#endif
})";

// The material assembled into every program that takes one compiles, after "#line 1 1".
TEST(GlslCheck, AHostMaterialCompilesIntoEveryProgramThatTakesOne) {
  skipWithoutGlslang();
  const detail::ShaderConfig config = checkConfig(819);
  detail::MaterialSource material;
  material.name = "gbuffer";
  material.text = kGbufferMaterial;
  material.depth_discard = true;
  int shaded = 0, depth = 0;
  forEachStage([&](ProgramId id, ShaderStage stage) {
    if (stage != ShaderStage::kFragment || !detail::takesMaterial(id, material)) return;
    std::string source;
    ASSERT_TRUE(detail::assembleStage(id, stage, config, &source, &material).isOk());
    EXPECT_NE(source.find(std::string("#line 1 1\n") + kGbufferMaterial), std::string::npos);
    EXPECT_EQ(compileWithGlslang(source, "frag", fileName(id, "material_", "")), "");
    ++(detail::materialUse(id) == detail::MaterialUse::kDepth ? depth : shaded);
  });
  // Every colour program of every path (25, the pulling draws' tangent variants included: the
  // impostor capture keeps its own material) and every depth-only program of a mesh (7).
  EXPECT_EQ(shaded, 25);
  EXPECT_EQ(depth, 7);
  // Without depth_discard the depth-only programs keep depth.frag.glsl.
  material.depth_discard = false;
  std::string source;
  ASSERT_TRUE(detail::assembleStage(ProgramId::kDepthOnly, ShaderStage::kFragment, config, &source,
                                    &material)
                  .isOk());
  EXPECT_EQ(source.find("siMaterial"), std::string::npos);
}

// A material that reads the instance handle (MaterialDesc::instance_handle): both stages of
// every program that takes it get SI_INSTANCE_HANDLE and compile; the others do not.
TEST(GlslCheck, TheInstanceHandleVariantsCompileWithGlslang) {
  skipWithoutGlslang();
  const detail::ShaderConfig config = checkConfig(819);
  detail::MaterialSource material;
  material.name = "handles";
  material.text =
      "layout(location = 0) out vec4 o;\n"
      "void siMaterial(SiSurface s) {\n"
      "  if (s.instance == 7u) discard;\n"
      "  o = unpackUnorm4x8(s.instance);\n"
      "}\n";
  material.depth_discard = true;
  material.instance_handle = true;
  int programs = 0;
  for (size_t p = 0; p < detail::kProgramCount; ++p) {
    const ProgramId id = ProgramId(p);
    const bool takes = detail::takesMaterial(id, material);
    programs += takes;
    for (ShaderStage stage :
         {ShaderStage::kVertex, ShaderStage::kFragment, ShaderStage::kCompute}) {
      if (detail::programSpec(id).file(stage) == nullptr) continue;
      std::string source;
      ASSERT_TRUE(detail::assembleStage(id, stage, config, &source, &material).isOk());
      EXPECT_EQ(source.find("#define SI_INSTANCE_HANDLE\n") != std::string::npos, takes)
          << detail::programSpec(id).name;
      if (takes) {
        EXPECT_EQ(compileWithGlslang(source, stageExtension(stage), fileName(id, "", "_handle")),
                  "");
      }
    }
  }
  EXPECT_EQ(programs, 25 + 7);  // As AHostMaterialCompilesIntoEveryProgramThatTakesOne counts.
}

TEST(GlslCheck, AssembleNamesAMissingStage) {
  std::string source;
  EXPECT_EQ(detail::assembleStage(ProgramId::kCull, ShaderStage::kVertex, {}, &source).code(),
            StatusCode::kInvalidArgument);
  EXPECT_TRUE(source.empty());
}

// The docs' user shader (include/si/gl/skinning_glsl.h), on the include as shipped.
std::string userShader(const std::string& defines) {
  return "#version 450 core\n" + defines + skinningGlsl() + R"(
layout(location = 0) in vec3 a_position;
layout(location = 3) in uvec4 a_joints;
layout(location = 4) in vec4 a_weights;
layout(location = 1) uniform mat4 u_view_projection;
out vec3 v_tint;
out vec3 v_own;
flat out int v_custom_layer;
// A host's own rows through the include's 4-influence sum.
void ownSkin(SiInstance inst, uvec4 joints, vec4 weights, out vec4 m0, out vec4 m1, out vec4 m2) {
  SI_SKIN_SUM(joints, weights, siInstanceJointRows(inst, joint, r0, r1, r2); r0 = -r0)
}
void main() {
  SiInstance inst = si_instances[gl_InstanceID];
  v_tint = siInstanceTint(inst);
  v_custom_layer = siInstanceCustomLayer(inst);
  vec4 m0, m1, m2;
  siSkin(inst, a_joints, a_weights, m0, m1, m2);
  vec3 model = siTransformPoint(m0, m1, m2, a_position);
  vec3 world = siTransformPoint(inst.world_rows[0], inst.world_rows[1], inst.world_rows[2], model);
  gl_Position = u_view_projection * vec4(world, 1.0);
  ownSkin(inst, a_joints, a_weights, m0, m1, m2);
  v_own = siPlacePoint(inst, m0, m1, m2, a_position);
}
)";
}

TEST(GlslCheck, UserShaderOnThePublicIncludeCompiles) {
  skipWithoutGlslang();
  EXPECT_EQ(compileWithGlslang(userShader("#define SI_MAX_INSTANCES 819\n"), "vert", "user_ubo"),
            "");
  EXPECT_EQ(compileWithGlslang(userShader("#define SI_INSTANCES_IN_STORAGE\n"), "vert",
                               "user_ssbo"),
            "");
  // Motion vectors and layered animation, in both record modes.
  for (const char* mode : {"#define SI_MAX_INSTANCES 819\n", "#define SI_INSTANCES_IN_STORAGE\n"})
    EXPECT_EQ(compileWithGlslang(userShader(std::string(mode) +
                                            "#define SI_PREVIOUS_RECORDS\n#define SI_LAYERS\n"),
                                 "vert", "user_previous_layers"),
              "");
  // The interface version is part of the include.
  EXPECT_NE(std::string(skinningGlsl()).find("#define SI_GLSL_INTERFACE_VERSION 12"),
            std::string::npos);
}

// The ES profile: its programs compile as GLSL ES 3.00 (WebGL 2's), the others are refused by
// the catalog, and the docs' user shader compiles on the include under "#version 300 es".
TEST(GlslCheck, TheEsProfilesProgramsCompileAsGlslEs300) {
  skipWithoutGlslang();
  detail::ShaderConfig config = checkConfig(204);
  config.es = true;
  int compiled = 0;
  forEachStage([&](ProgramId id, ShaderStage stage) {
    std::string source;
    const Status s = detail::assembleStage(id, stage, config, &source);
    if (!detail::esProgram(id)) {
      EXPECT_EQ(s.code(), StatusCode::kUnsupported) << detail::programSpec(id).name;
      return;
    }
    ASSERT_TRUE(s.isOk()) << s.toString();
    ASSERT_EQ(source.rfind("#version 300 es\n", 0), 0u);
    EXPECT_EQ(compileWithGlslang(source, stageExtension(stage), fileName(id, "es_", "")), "");
    ++compiled;
  });
  EXPECT_EQ(compiled, 3 * 2);  // Skinned, depth-only and rigid: a vertex and a fragment stage.
  std::string user = userShader("#define SI_MAX_INSTANCES 204\n");
  const std::string located = "layout(location = 1) uniform mat4";
  user.replace(user.find(located), located.size(), "uniform mat4");
  user.replace(0, user.find('\n'),
               "#version 300 es\nprecision highp float;\nprecision highp int;\n"
               "precision highp sampler2D;");
  EXPECT_EQ(compileWithGlslang(user, "vert", "user_es"), "");
}

// The docs' Vulkan user shader: gl_InstanceIndex, the host's own uniforms in a block, every
// binding of the include moved by its define into descriptor set 2 (docs/glsl-interface.md,
// "Moving the bindings").
std::string vulkanUserShader(const std::string& records) {
  return "#version 450\n" + records + R"(
#define SI_PREVIOUS_RECORDS
#define SI_LAYERS
#define SI_DESCRIPTOR_SET 2
#define SI_RECORDS_BINDING 10
#define SI_PALETTE_BINDING 11
#define SI_PALETTE_INFO_BINDING 12
#define SI_PREVIOUS_BINDING 13
#define SI_LAYER_BINDING 14
#define SI_PREVIOUS_LAYER_BINDING 15
#define SI_MASK_BINDING 16
)" + std::string(skinningGlsl()) + R"(
layout(location = 0) in vec3 a_position;
layout(location = 3) in uvec4 a_joints;
layout(location = 4) in vec4 a_weights;
layout(std140, set = 0, binding = 0) uniform Camera { mat4 u_view_projection; };
layout(location = 0) out vec3 v_previous;
void main() {
  uint slot = uint(gl_InstanceIndex);
  SiInstance inst = si_instances[slot];
  vec4 m0, m1, m2;
  siSkinLayered(inst, si_layers[slot], a_joints, a_weights, m0, m1, m2);
  vec3 world = siTransformPoint(inst.world_rows[0], inst.world_rows[1], inst.world_rows[2],
                                siTransformPoint(m0, m1, m2, a_position));
  v_previous = siSkinPreviousLayered(slot, a_joints, a_weights, a_position);
  gl_Position = u_view_projection * vec4(world, 1.0);
}
)";
}

// Compiles `source` for Vulkan 1.1 (SPIR-V) and returns the spirv-dis text, or "" with the
// error in `error`.
std::string compileForVulkan(const std::string& source, const std::string& name,
                             std::string* error) {
  const std::string file = ::testing::TempDir() + "si_glsl_vk_" + name + ".vert";
  const std::string log = file + ".log", spv = file + ".spv", dis = file + ".spvasm";
  std::ofstream(file, std::ios::binary) << source;
  const std::string compile = "glslangValidator -V --target-env vulkan1.1 '" + file + "' -o '" +
                              spv + "' >'" + log + "' 2>&1";
  if (std::system(compile.c_str()) != 0) {
    *error = "glslangValidator -V failed on " + file + ":\n" + readFile(log);
    return "";
  }
  const std::string disassemble = "spirv-dis '" + spv + "' -o '" + dis + "' >'" + log + "' 2>&1";
  if (std::system(disassemble.c_str()) != 0) {
    *error = "spirv-dis failed on " + spv + ":\n" + readFile(log);
    return "";
  }
  return readFile(dis);
}

// Every (set, binding) decoration of a spirv-dis listing, as "set:binding", sorted.
std::vector<std::string> descriptorBindings(const std::string& spirv) {
  std::map<std::string, std::pair<std::string, std::string>> by_id;
  std::istringstream in(spirv);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string op, id, decoration, value;
    words >> op >> id >> decoration >> value;
    if (op != "OpDecorate") continue;
    if (decoration == "DescriptorSet") by_id[id].first = value;
    if (decoration == "Binding") by_id[id].second = value;
  }
  std::vector<std::string> out;
  for (const auto& [id, sb] : by_id) out.push_back(sb.first + ":" + sb.second);
  std::sort(out.begin(), out.end());
  return out;
}

TEST(GlslCheck, TheIncludeCompilesForVulkanWithEveryBindingMoved) {
  skipWithoutGlslang();
  if (std::system("spirv-dis --version >/dev/null 2>&1") != 0) {
    if (std::getenv("SI_REQUIRE_GLSLANG") != nullptr)
      FAIL() << "spirv-dis not found (install spirv-tools: scripts/deps.sh)";
    GTEST_SKIP() << "spirv-dis not found (Debian package spirv-tools)";
  }
  for (const char* records : {"#define SI_MAX_INSTANCES 819\n", "#define SI_INSTANCES_IN_STORAGE\n"}) {
    SCOPED_TRACE(records);
    std::string error;
    const std::string spirv = compileForVulkan(vulkanUserShader(records), "moved", &error);
    ASSERT_EQ(error, "");
    // The host's camera block, and each of the include's seven resources where its define put
    // it: a binding left fixed in the include would show up at its old number or set.
    EXPECT_EQ(descriptorBindings(spirv),
              (std::vector<std::string>{"0:0", "2:10", "2:11", "2:12", "2:13", "2:14", "2:15",
                                        "2:16"}));
  }
}

TEST(GlslCheck, UserShaderWithoutCapacityFailsToCompile) {
  skipWithoutGlslang();  // The check above could not fail if this one passed.
  EXPECT_NE(compileWithGlslang(userShader(""), "vert", "user_no_capacity"), "");
}

// A tiny include resolver, as an engine's would be: `#include "x"` replaced by x's text.
std::string resolveIncludes(const std::string& dir, const std::string& name, int depth = 0) {
  std::istringstream in(readFile(dir + "/" + name));
  std::string line, out;
  while (std::getline(in, line)) {
    const size_t at = line.find("#include \"");
    if (at == 0 && depth < 16) {
      const size_t end = line.find('"', 10);
      out += resolveIncludes(dir, line.substr(10, end - 10), depth + 1);
    } else {
      out += line + "\n";
    }
  }
  return out;
}

TEST(GlslCheck, EmbeddedIncludeEqualsTheSourceFiles) {
  const std::string resolved = resolveIncludes(SI_GLSL_DIR, "si_skinning.glsl");
  ASSERT_GT(resolved.size(), 1000u) << "could not read " << SI_GLSL_DIR << "/si_skinning.glsl";
  EXPECT_EQ(resolved, std::string(skinningGlsl()));
}

}  // namespace
}  // namespace si
