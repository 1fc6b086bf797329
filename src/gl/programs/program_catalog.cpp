// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The table of programs: shader files and defines of each.
#include "gl/programs/program_catalog.h"

#include <cstring>

#include "core/str_cat.h"
#include "gl/programs/embedded_shaders.h"

namespace si::detail {

namespace {

// Indexed by ProgramId.
const ProgramSpec kSpecs[kProgramCount] = {
    {"skinned", "", "skinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"depth-only", "", "skinned.vert.glsl", "depth.frag.glsl", nullptr, nullptr},
    {"rigid", "#define SI_RIGID\n", "skinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"traditional", "#define SI_TRADITIONAL\n", "skinned.vert.glsl", "surface.frag.glsl", nullptr,
     nullptr},
    {"capture", "#define SI_CAPTURE\n", "skinned.vert.glsl", "depth.frag.glsl", nullptr,
     "tf_position"},
    {"pre-skinned", "", "preskinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"compute skinning", "", nullptr, nullptr, "compute_skin.comp.glsl", nullptr},
    {"pre-skinned pulling", "", "pulled.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"GPU-driven skinned", "#define SI_GPU_DRIVEN\n", "skinned.vert.glsl", "surface.frag.glsl",
     nullptr, nullptr},
    {"GPU culling", "", nullptr, nullptr, "cull.comp.glsl", nullptr},
    {"GPU culling commands", "", nullptr, nullptr, "cull_commands.comp.glsl", nullptr},
    {"GPU culling scatter", "", nullptr, nullptr, "cull_scatter.comp.glsl", nullptr},
    {"GPU-driven pre-skinning", "", nullptr, nullptr, "gpu_skin.comp.glsl", nullptr},
    {"GPU-driven pulling", "#define SI_GPU_DRIVEN\n", "pulled.vert.glsl", "surface.frag.glsl",
     nullptr, nullptr},
    {"depth pyramid copy", "#define SI_HIZ_COPY\n", nullptr, nullptr, "hiz.comp.glsl", nullptr},
    {"depth pyramid reduce", "", nullptr, nullptr, "hiz.comp.glsl", nullptr},
    {"skinned with motion vectors", "#define SI_MOTION_VECTORS\n", "skinned.vert.glsl",
     "surface.frag.glsl", nullptr, nullptr},
    {"compute skinning with previous positions", "#define SI_MOTION_VECTORS\n", nullptr, nullptr,
     "compute_skin.comp.glsl", nullptr},
    {"pre-skinned pulling with motion vectors", "#define SI_MOTION_VECTORS\n", "pulled.vert.glsl",
     "surface.frag.glsl", nullptr, nullptr},
    {"skinned with layers", "#define SI_LAYERS\n", "skinned.vert.glsl", "surface.frag.glsl",
     nullptr, nullptr},
    {"compute skinning with layers", "#define SI_LAYERS\n", nullptr, nullptr,
     "compute_skin.comp.glsl", nullptr},
    {"depth-only with layers", "#define SI_LAYERS\n", "skinned.vert.glsl", "depth.frag.glsl",
     nullptr, nullptr},
    {"GPU-driven skinned with layers", "#define SI_GPU_DRIVEN\n#define SI_LAYERS\n",
     "skinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"GPU-driven pre-skinning with layers", "#define SI_LAYERS\n", nullptr, nullptr,
     "gpu_skin.comp.glsl", nullptr},
    {"skinned with motion vectors and layers", "#define SI_MOTION_VECTORS\n#define SI_LAYERS\n",
     "skinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"compute skinning with previous positions and layers",
     "#define SI_MOTION_VECTORS\n#define SI_LAYERS\n", nullptr, nullptr, "compute_skin.comp.glsl",
     nullptr},
    {"GPU-driven skinned with motion vectors", "#define SI_GPU_DRIVEN\n#define SI_MOTION_VECTORS\n",
     "skinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"GPU-driven pre-skinning with previous positions", "#define SI_MOTION_VECTORS\n", nullptr,
     nullptr, "gpu_skin.comp.glsl", nullptr},
    {"GPU-driven pulling with motion vectors", "#define SI_GPU_DRIVEN\n#define SI_MOTION_VECTORS\n",
     "pulled.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"GPU-driven skinned with motion vectors and layers",
     "#define SI_GPU_DRIVEN\n#define SI_MOTION_VECTORS\n#define SI_LAYERS\n", "skinned.vert.glsl",
     "surface.frag.glsl", nullptr, nullptr},
    {"GPU-driven pre-skinning with previous positions and layers",
     "#define SI_MOTION_VECTORS\n#define SI_LAYERS\n", nullptr, nullptr, "gpu_skin.comp.glsl",
     nullptr},
    {"GPU-driven depth-only", "#define SI_GPU_DRIVEN\n", "skinned.vert.glsl", "depth.frag.glsl",
     nullptr, nullptr},
    {"GPU-driven depth-only with layers", "#define SI_GPU_DRIVEN\n#define SI_LAYERS\n",
     "skinned.vert.glsl", "depth.frag.glsl", nullptr, nullptr},
    {"GPU-driven pulling, depth only", "#define SI_GPU_DRIVEN\n", "pulled.vert.glsl",
     "depth.frag.glsl", nullptr, nullptr},
    {"impostor capture", "", "skinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"impostor", "", "impostor.vert.glsl", "impostor.frag.glsl", nullptr, nullptr},
    {"impostor, depth only", "#define SI_DEPTH_ONLY\n", "impostor.vert.glsl", "impostor.frag.glsl",
     nullptr, nullptr},
    {"GPU-driven impostor", "#define SI_GPU_DRIVEN\n", "impostor.vert.glsl", "impostor.frag.glsl",
     nullptr, nullptr},
    {"GPU-driven impostor, depth only", "#define SI_GPU_DRIVEN\n#define SI_DEPTH_ONLY\n",
     "impostor.vert.glsl", "impostor.frag.glsl", nullptr, nullptr},
    {"layer compose", "", nullptr, nullptr, "layer_compose.comp.glsl", nullptr},
    {"layer compose with previous records", "#define SI_MOTION_VECTORS\n", nullptr, nullptr,
     "layer_compose.comp.glsl", nullptr},
    {"skinned with composed layers", "#define SI_LAYERS\n#define SI_COMPOSED_LAYERS\n",
     "skinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"skinned with motion vectors and composed layers",
     "#define SI_MOTION_VECTORS\n#define SI_LAYERS\n#define SI_COMPOSED_LAYERS\n",
     "skinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"depth-only with composed layers", "#define SI_LAYERS\n#define SI_COMPOSED_LAYERS\n",
     "skinned.vert.glsl", "depth.frag.glsl", nullptr, nullptr},
    {"GPU-driven layer compose", "#define SI_GPU_DRIVEN\n", nullptr, nullptr,
     "layer_compose.comp.glsl", nullptr},
    {"GPU-driven layer compose with previous records",
     "#define SI_GPU_DRIVEN\n#define SI_MOTION_VECTORS\n", nullptr, nullptr,
     "layer_compose.comp.glsl", nullptr},
    {"GPU-driven skinned with composed layers",
     "#define SI_GPU_DRIVEN\n#define SI_LAYERS\n#define SI_COMPOSED_LAYERS\n", "skinned.vert.glsl",
     "surface.frag.glsl", nullptr, nullptr},
    {"GPU-driven skinned with motion vectors and composed layers",
     "#define SI_GPU_DRIVEN\n#define SI_MOTION_VECTORS\n#define SI_LAYERS\n"
     "#define SI_COMPOSED_LAYERS\n",
     "skinned.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"GPU-driven depth-only with composed layers",
     "#define SI_GPU_DRIVEN\n#define SI_LAYERS\n#define SI_COMPOSED_LAYERS\n", "skinned.vert.glsl",
     "depth.frag.glsl", nullptr, nullptr},
    {"compute skinning with composed layers", "#define SI_LAYERS\n#define SI_COMPOSED_LAYERS\n",
     nullptr, nullptr, "compute_skin.comp.glsl", nullptr},
    {"compute skinning with previous positions and composed layers",
     "#define SI_MOTION_VECTORS\n#define SI_LAYERS\n#define SI_COMPOSED_LAYERS\n", nullptr, nullptr,
     "compute_skin.comp.glsl", nullptr},
    {"GPU-driven pre-skinning with composed layers",
     "#define SI_LAYERS\n#define SI_COMPOSED_LAYERS\n", nullptr, nullptr, "gpu_skin.comp.glsl",
     nullptr},
    {"GPU-driven pre-skinning with previous positions and composed layers",
     "#define SI_MOTION_VECTORS\n#define SI_LAYERS\n#define SI_COMPOSED_LAYERS\n", nullptr, nullptr,
     "gpu_skin.comp.glsl", nullptr},
    {"staged upload scatter", "", nullptr, nullptr, "upload_scatter.comp.glsl", nullptr},
    {"depth pyramid copy, multisampled", "#define SI_HIZ_COPY\n#define SI_HIZ_MULTISAMPLE\n",
     nullptr, nullptr, "hiz.comp.glsl", nullptr},
    {"pre-skinned pulling with tangents", "#define SI_TANGENTS\n", "pulled.vert.glsl",
     "surface.frag.glsl", nullptr, nullptr},
    {"pre-skinned pulling with motion vectors and tangents",
     "#define SI_MOTION_VECTORS\n#define SI_TANGENTS\n", "pulled.vert.glsl", "surface.frag.glsl",
     nullptr, nullptr},
    {"GPU-driven pulling with tangents", "#define SI_GPU_DRIVEN\n#define SI_TANGENTS\n",
     "pulled.vert.glsl", "surface.frag.glsl", nullptr, nullptr},
    {"GPU-driven pulling with motion vectors and tangents",
     "#define SI_GPU_DRIVEN\n#define SI_MOTION_VECTORS\n#define SI_TANGENTS\n", "pulled.vert.glsl",
     "surface.frag.glsl", nullptr, nullptr},
    {"GPU-driven impostor quads", "", nullptr, nullptr, "impostor_quads.comp.glsl", nullptr},
    {"impostor coverage", "", nullptr, nullptr, "impostor_coverage.comp.glsl", nullptr},
    {"impostor coverage rectangles", "#define SI_COVERAGE_RECTS\n", nullptr, nullptr,
     "impostor_coverage.comp.glsl", nullptr},
    {"impostor capture resolve", "", nullptr, nullptr, "impostor_resolve.comp.glsl", nullptr},
};

}  // namespace

const char* embeddedShader(const char* name) {
  for (size_t i = 0; i < kEmbeddedShaderCount; ++i)
    if (std::strcmp(kEmbeddedShaders[i].name, name) == 0) return kEmbeddedShaders[i].source;
  return nullptr;
}

const ProgramSpec& programSpec(ProgramId id) { return kSpecs[size_t(id) % kProgramCount]; }

ProgramId pullingProgram(bool gpu_driven, bool motion, bool tangents) {
  // [gpu_driven][motion][tangents]
  static constexpr ProgramId kTable[2][2][2] = {
      {{ProgramId::kPulled, ProgramId::kPulledTangents},
       {ProgramId::kPulledMotion, ProgramId::kPulledMotionTangents}},
      {{ProgramId::kGpuPulled, ProgramId::kGpuPulledTangents},
       {ProgramId::kGpuPulledMotion, ProgramId::kGpuPulledMotionTangents}}};
  return kTable[gpu_driven ? 1 : 0][motion ? 1 : 0][tangents ? 1 : 0];
}

ProgramId skinningProgram(bool gpu_driven, bool depth_only, bool motion, bool layers,
                          bool composed) {
  // [gpu_driven][depth-only, shaded, shaded with motion][plain, layers, composed]
  static constexpr ProgramId kTable[2][3][3] = {
      {{ProgramId::kDepthOnly, ProgramId::kDepthOnlyLayers, ProgramId::kDepthOnlyComposed},
       {ProgramId::kSkinned, ProgramId::kSkinnedLayers, ProgramId::kSkinnedComposed},
       {ProgramId::kSkinnedMotion, ProgramId::kSkinnedMotionLayers,
        ProgramId::kSkinnedMotionComposed}},
      {{ProgramId::kGpuDrivenDepthOnly, ProgramId::kGpuDrivenDepthOnlyLayers,
        ProgramId::kGpuDrivenDepthOnlyComposed},
       {ProgramId::kGpuDrivenSkinned, ProgramId::kGpuDrivenSkinnedLayers,
        ProgramId::kGpuDrivenSkinnedComposed},
       {ProgramId::kGpuDrivenSkinnedMotion, ProgramId::kGpuDrivenSkinnedMotionLayers,
        ProgramId::kGpuDrivenSkinnedMotionComposed}}};
  return kTable[gpu_driven ? 1 : 0][depth_only ? 0
                                    : motion   ? 2
                                               : 1][composed && layers ? 2
                                                  : layers           ? 1
                                                                     : 0];
}

ProgramId preSkinningProgram(bool gpu_driven, bool motion, bool layers, bool composed) {
  // [gpu_driven][plain, with previous positions][plain, layers, composed]
  static constexpr ProgramId kTable[2][2][3] = {
      {{ProgramId::kComputeSkin, ProgramId::kComputeSkinLayers, ProgramId::kComputeSkinComposed},
       {ProgramId::kComputeSkinMotion, ProgramId::kComputeSkinMotionLayers,
        ProgramId::kComputeSkinMotionComposed}},
      {{ProgramId::kGpuSkin, ProgramId::kGpuSkinLayers, ProgramId::kGpuSkinComposed},
       {ProgramId::kGpuSkinMotion, ProgramId::kGpuSkinMotionLayers,
        ProgramId::kGpuSkinMotionComposed}}};
  return kTable[gpu_driven ? 1 : 0][motion ? 1 : 0][composed && layers ? 2 : layers ? 1 : 0];
}

MaterialUse materialUse(ProgramId id) {
  const ProgramSpec& spec = programSpec(id);
  if (id == ProgramId::kImpostorCapture) return MaterialUse::kCapture;
  if (spec.fragment == nullptr || id == ProgramId::kCapture) return MaterialUse::kNone;
  const std::string fragment = spec.fragment;
  if (fragment == "surface.frag.glsl") return MaterialUse::kShaded;
  if (fragment == "depth.frag.glsl") return MaterialUse::kDepth;
  // impostor.frag.glsl: shaded, or (SI_DEPTH_ONLY) the atlas's coverage test alone.
  return std::strstr(spec.defines, "SI_DEPTH_ONLY") != nullptr ? MaterialUse::kNone
                                                               : MaterialUse::kShaded;
}

bool readsVertexWords(ProgramId id) {
  const MaterialUse use = materialUse(id);
  const ProgramSpec& spec = programSpec(id);
  return (use == MaterialUse::kShaded || use == MaterialUse::kCapture) &&
         std::strcmp(spec.fragment, "surface.frag.glsl") == 0;
}

bool skinsVertices(ProgramId id) {
  const ProgramSpec& spec = programSpec(id);
  if (spec.vertex != nullptr)
    return std::strcmp(spec.vertex, "skinned.vert.glsl") == 0 &&
           std::strstr(spec.defines, "SI_RIGID") == nullptr;
  return spec.compute != nullptr && (std::strcmp(spec.compute, "compute_skin.comp.glsl") == 0 ||
                                     std::strcmp(spec.compute, "gpu_skin.comp.glsl") == 0);
}

bool composesLayers(ProgramId id) {
  const ProgramSpec& spec = programSpec(id);
  return spec.compute != nullptr && std::strcmp(spec.compute, "layer_compose.comp.glsl") == 0;
}

bool takesMaterial(ProgramId id, const MaterialSource& material) {
  const MaterialUse use = materialUse(id);
  return use == MaterialUse::kShaded || (use == MaterialUse::kDepth && material.depth_discard);
}

bool esProgram(ProgramId id) {
  return id == ProgramId::kSkinned || id == ProgramId::kDepthOnly || id == ProgramId::kRigid;
}

const EsBinding* esBindings(size_t* count) {
  // The desktop shaders' layout qualifiers: si_skinning.glsl's defaults, surface.frag.glsl's and
  // surface_common.glsl's samplers, material_common.glsl's table (a uniform block on ES).
  static const EsBinding kBindings[] = {
      {"SiInstances", false, 0},    {"SiPaletteInfo", false, 4}, {"SiMaterials", false, 11},
      {"si_palette", true, 0},      {"u_base_color", true, 1},   {"u_custom", true, 2},
      {"u_material_data", true, 4}, {"si_morphs", true, 5},
  };
  *count = sizeof(kBindings) / sizeof(kBindings[0]);
  return kBindings;
}

Status assembleStage(ProgramId id, ShaderStage stage, const ShaderConfig& config,
                     std::string* out, const MaterialSource* material) {
  const ProgramSpec& spec = programSpec(id);
  const char* file = spec.file(stage);
  // The fragment stage's material: its text after the stage's file (which declares siMaterial).
  const char* material_file = nullptr;
  std::string material_defines;
  if (material != nullptr && material->instance_handle && takesMaterial(id, *material))
    material_defines = "#define SI_INSTANCE_HANDLE\n";
  if (stage != ShaderStage::kFragment) {
    material = nullptr;  // Only the fragment stage takes a material.
  } else {
    const MaterialUse use = materialUse(id);
    const bool discards = material != nullptr && material->depth_discard;
    if (use == MaterialUse::kShaded) {
      material_file = "builtin_material.glsl";
    } else if (use == MaterialUse::kCapture) {
      material_file = "impostor_capture_material.glsl";
      material = nullptr;
    } else if (use == MaterialUse::kDepth && discards) {
      file = "surface.frag.glsl";
      material_defines += "#define SI_DEPTH_ONLY\n";
    } else {
      material = nullptr;
    }
  }
  if (file == nullptr)
    return {StatusCode::kInvalidArgument,
            strCat("program ", spec.name, " has no ", shaderStageName(stage), " shader")};
  const char* text = embeddedShader(file);
  if (text == nullptr)
    return {StatusCode::kNotFound, strCat("program ", spec.name, ": shader file ", file,
                                          " was not embedded (cmake/SiEmbedGlsl.cmake)")};
  if (config.es && !esProgram(id))
    return {StatusCode::kUnsupported,
            strCat("program ", spec.name, " is not in the OpenGL ES profile")};
  const char* version = config.es
                            ? "#version 300 es\nprecision highp float;\nprecision highp int;\n"
                              "precision highp sampler2D;\nprecision highp sampler2DArray;\n"
                            : "#version 450 core\n";
  std::string material_text;
  if (material != nullptr) {
    material_text = material->text;
  } else if (material_file != nullptr) {
    const char* builtin = embeddedShader(material_file);
    if (builtin == nullptr)
      return {StatusCode::kNotFound, strCat("program ", spec.name, ": shader file ",
                                            material_file, " was not embedded")};
    material_text = builtin;
  }
  *out = strCat(
      version, "#define SI_MAX_INSTANCES ", config.max_instances, "\n#define SI_MAX_JOINTS ",
      config.max_joints, "\n",
      config.es ? strCat("#define SI_MAX_MATERIALS ", kEsMaxMaterials, "\n") : "",
      config.vertex_words ? "#define SI_VERTEX_WORDS\n" : "",
      config.eight_influences ? "#define SI_EIGHT_INFLUENCES\n" : "",
      config.morph_targets ? "#define SI_MORPH_TARGETS\n" : "",
      config.mask_binding != 0 ? strCat("#define SI_MASK_BINDING ", config.mask_binding, "\n") : "",
      spec.defines, material_defines, text);
  // The material's lines are numbered from 1 as source string 1 in the compiler's log.
  if (material != nullptr || material_file != nullptr)
    *out += strCat("\n#line 1 1\n", material_text, "\n");
  return Status::ok();
}

}  // namespace si::detail
