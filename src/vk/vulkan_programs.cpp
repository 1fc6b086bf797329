// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "vk/vulkan_programs.h"

#include <vector>

namespace si::vk::detail {

namespace {

using si::detail::ProgramId;

constexpr VulkanKind kKinds[] = {VulkanKind::kShaded, VulkanKind::kDepthOnly, VulkanKind::kMotion};

// The catalog's program of `kind`, with the overlays on their masks or not, of drawCrowd's
// path or the GPU-driven one.
ProgramId catalogProgram(VulkanKind kind, bool layers, bool composed, bool gpu_driven) {
  if (gpu_driven && composed)
    return kind == VulkanKind::kDepthOnly ? ProgramId::kGpuDrivenDepthOnlyComposed
           : kind == VulkanKind::kMotion  ? ProgramId::kGpuDrivenSkinnedMotionComposed
                                          : ProgramId::kGpuDrivenSkinnedComposed;
  if (gpu_driven && layers)
    return kind == VulkanKind::kDepthOnly ? ProgramId::kGpuDrivenDepthOnlyLayers
           : kind == VulkanKind::kMotion  ? ProgramId::kGpuDrivenSkinnedMotionLayers
                                          : ProgramId::kGpuDrivenSkinnedLayers;
  if (gpu_driven)
    return kind == VulkanKind::kDepthOnly ? ProgramId::kGpuDrivenDepthOnly
           : kind == VulkanKind::kMotion  ? ProgramId::kGpuDrivenSkinnedMotion
                                          : ProgramId::kGpuDrivenSkinned;
  switch (kind) {
    case VulkanKind::kDepthOnly:
      return layers ? ProgramId::kDepthOnlyLayers : ProgramId::kDepthOnly;
    case VulkanKind::kMotion:
      return layers ? ProgramId::kSkinnedMotionLayers : ProgramId::kSkinnedMotion;
    case VulkanKind::kShaded:
      break;
  }
  return layers ? ProgramId::kSkinnedLayers : ProgramId::kSkinned;
}

// The GPU-driven pre-skinning pass, skinning the previous positions too or not, with the
// overlays on their masks or not.
ProgramId gpuSkinProgram(bool motion, bool layers, bool composed) {
  if (motion)
    return composed ? ProgramId::kGpuSkinMotionComposed
           : layers ? ProgramId::kGpuSkinMotionLayers
                    : ProgramId::kGpuSkinMotion;
  return composed ? ProgramId::kGpuSkinComposed
         : layers ? ProgramId::kGpuSkinLayers
                  : ProgramId::kGpuSkin;
}

// Layering: 0 none, 1 the overlays composed per vertex ("_layers"), 2 the compose pass's rows
// read ("_composed": GPU-driven only).
constexpr int kLayerings[] = {0, 1, 2};
const char* layeringName(int layering) {
  return layering == 1 ? "_layers" : layering == 2 ? "_composed" : "";
}

std::vector<VulkanProgram> makePrograms() {
  std::vector<VulkanProgram> programs;
  for (bool gpu_driven : {false, true})
    for (bool morph : {false, true})
      for (int layering : kLayerings)
        for (bool eight : {false, true})
          for (bool words : {false, true})
            for (VulkanKind kind : kKinds) {
              if (words && kind == VulkanKind::kDepthOnly) continue;  // It reads no vertex words.
              if (layering == 2 && !gpu_driven) continue;  // drawCrowd's path composes none yet.
              const bool layers = layering != 0, composed = layering == 2;
              std::string name = kind == VulkanKind::kShaded      ? "skinned"
                                 : kind == VulkanKind::kDepthOnly ? "depth_only"
                                                                  : "skinned_motion";
              if (gpu_driven) name = "gpu_" + name;
              name += layeringName(layering);
              if (morph) name += "_morph";
              if (eight) name += "_8";
              if (words) name += "_words";
              programs.push_back({catalogProgram(kind, layers, composed, gpu_driven), kind,
                                  gpu_driven, false, false, false, false, layers, morph, eight,
                                  words, name, composed});
            }
  for (bool tangents : {false, true})
    for (bool words : {false, true})
      programs.push_back(
          {tangents ? ProgramId::kGpuPulledTangents : ProgramId::kGpuPulled, VulkanKind::kShaded,
           true, false, true, tangents, false, false, false, false, words,
           std::string("gpu_pulled") + (tangents ? "_tangents" : "") + (words ? "_words" : "")});
  programs.push_back({ProgramId::kGpuPulledDepthOnly, VulkanKind::kDepthOnly, true, false, true,
                      false, false, false, false, false, false, "gpu_pulled_depth_only"});
  for (bool tangents : {false, true})
    for (bool words : {false, true})
      programs.push_back(
          {tangents ? ProgramId::kGpuPulledMotionTangents : ProgramId::kGpuPulledMotion,
           VulkanKind::kMotion, true, false, true, tangents, false, false, false, false, words,
           std::string("gpu_pulled_motion") + (tangents ? "_tangents" : "") +
               (words ? "_words" : "")});
  for (bool morph : {false, true})
    for (bool eight : {false, true})
      for (bool words : {false, true})
        programs.push_back({ProgramId::kImpostorCapture, VulkanKind::kShaded, false, false, false,
                            false, true, false, morph, eight, words,
                            std::string("impostor_capture") + (morph ? "_morph" : "") +
                                (eight ? "_8" : "") + (words ? "_words" : "")});
  programs.push_back({ProgramId::kGpuDrivenImpostor, VulkanKind::kShaded, true, false, false, false,
                      true, false, false, false, false, "gpu_impostor"});
  programs.push_back({ProgramId::kGpuDrivenImpostorDepthOnly, VulkanKind::kDepthOnly, true, false,
                      false, false, true, false, false, false, false, "gpu_impostor_depth_only"});
  for (const auto& [id, name] :
       {std::pair{ProgramId::kCull, "cull"}, std::pair{ProgramId::kCullCommands, "cull_commands"},
        std::pair{ProgramId::kCullScatter, "cull_scatter"}})
    programs.push_back({id, VulkanKind::kShaded, true, true, false, false, false, false, false,
                        false, false, std::string(name)});
  for (bool motion : {false, true})
    for (int layering : kLayerings)
      for (bool morph : {false, true})
        for (bool eight : {false, true})
          programs.push_back({gpuSkinProgram(motion, layering != 0, layering == 2),
                              motion ? VulkanKind::kMotion : VulkanKind::kShaded, true, true, false,
                              false, false, layering != 0, morph, eight, false,
                              std::string("gpu_skin") + (motion ? "_motion" : "") +
                                  layeringName(layering) + (morph ? "_morph" : "") +
                                  (eight ? "_8" : ""),
                              layering == 2});
  // The layer compose pass (its morph variant composes the weights too).
  for (bool motion : {false, true})
    for (bool morph : {false, true})
      programs.push_back(
          {motion ? ProgramId::kGpuLayerComposeMotion : ProgramId::kGpuLayerCompose,
           motion ? VulkanKind::kMotion : VulkanKind::kShaded, true, true, false, false, false,
           true, morph, false, false,
           std::string("gpu_layer_compose") + (motion ? "_motion" : "") + (morph ? "_morph" : ""),
           true});
  for (const auto& [id, name] :
       {std::pair{ProgramId::kHizCopy, "hiz_copy"},
        std::pair{ProgramId::kHizCopyMultisample, "hiz_copy_ms"},
        std::pair{ProgramId::kHizReduce, "hiz_reduce"},
        std::pair{ProgramId::kImpostorQuads, "impostor_quads"},
        std::pair{ProgramId::kImpostorCoverage, "impostor_coverage"},
        std::pair{ProgramId::kImpostorCoverageRects, "impostor_coverage_rects"},
        std::pair{ProgramId::kImpostorResolve, "impostor_resolve"}})
    programs.push_back({id, VulkanKind::kShaded, true, true, false, false, false, false, false,
                        false, false, std::string(name)});
  return programs;
}

const std::vector<VulkanProgram>& programList() {
  static const std::vector<VulkanProgram> programs = makePrograms();
  return programs;
}

}  // namespace

Span<const VulkanProgram> vulkanPrograms() {
  return Span<const VulkanProgram>(programList().data(), programList().size());
}

size_t vulkanProgramIndex(VulkanKind kind, bool layers, const MeshVariant& mesh, bool gpu_driven,
                          bool composed) {
  const bool words = mesh.vertex_words && kind != VulkanKind::kDepthOnly;
  const std::vector<VulkanProgram>& programs = programList();
  for (size_t k = 0; k < programs.size(); ++k)
    if (!programs[k].compute && !programs[k].pulled && !programs[k].impostor &&
        programs[k].gpu_driven == gpu_driven && programs[k].kind == kind &&
        programs[k].layers == layers && programs[k].composed == composed &&
        programs[k].morph_targets == mesh.morph_targets &&
        programs[k].eight_influences == mesh.eight_influences && programs[k].vertex_words == words)
      return k;
  return 0;  // makePrograms() lists every combination.
}

size_t vulkanComputeProgramIndex(ProgramId id, const MeshVariant& mesh) {
  const bool skin = id == ProgramId::kGpuSkin || id == ProgramId::kGpuSkinMotion ||
                    id == ProgramId::kGpuSkinLayers || id == ProgramId::kGpuSkinMotionLayers ||
                    id == ProgramId::kGpuSkinComposed || id == ProgramId::kGpuSkinMotionComposed;
  const bool compose = id == ProgramId::kGpuLayerCompose || id == ProgramId::kGpuLayerComposeMotion;
  const std::vector<VulkanProgram>& programs = programList();
  for (size_t k = 0; k < programs.size(); ++k)
    if (programs[k].compute && programs[k].id == id &&
        (!(skin || compose) || programs[k].morph_targets == mesh.morph_targets) &&
        (!skin || programs[k].eight_influences == mesh.eight_influences))
      return k;
  return 0;  // makePrograms() lists every pass and variant.
}

size_t vulkanCaptureProgramIndex(const MeshVariant& mesh) {
  const std::vector<VulkanProgram>& programs = programList();
  for (size_t k = 0; k < programs.size(); ++k)
    if (programs[k].id == ProgramId::kImpostorCapture &&
        programs[k].morph_targets == mesh.morph_targets &&
        programs[k].eight_influences == mesh.eight_influences &&
        programs[k].vertex_words == mesh.vertex_words)
      return k;
  return 0;  // makePrograms() lists every variant.
}

size_t vulkanImpostorProgramIndex(bool depth_only) {
  const ProgramId id =
      depth_only ? ProgramId::kGpuDrivenImpostorDepthOnly : ProgramId::kGpuDrivenImpostor;
  const std::vector<VulkanProgram>& programs = programList();
  for (size_t k = 0; k < programs.size(); ++k)
    if (programs[k].id == id) return k;
  return 0;  // makePrograms() lists both.
}

size_t vulkanPulledProgramIndex(VulkanKind kind, bool tangents, const MeshVariant& mesh) {
  const bool depth_only = kind == VulkanKind::kDepthOnly;
  const std::vector<VulkanProgram>& programs = programList();
  for (size_t k = 0; k < programs.size(); ++k)
    if (programs[k].pulled && programs[k].kind == kind &&
        (depth_only ||
         (programs[k].tangents == tangents && programs[k].vertex_words == mesh.vertex_words)))
      return k;
  return 0;  // makePrograms() lists every combination.
}

si::detail::ShaderConfig vulkanShaderConfig(const VulkanProgram& program) {
  si::detail::ShaderConfig config;
  config.max_instances = kVulkanMaxInstances;
  config.max_joints = 256;
  config.eight_influences = program.eight_influences;
  config.vertex_words = program.vertex_words;
  config.morph_targets = program.morph_targets;
  if (program.gpu_driven) config.mask_binding = kDrivenMaskStorageBinding;
  return config;
}

}  // namespace si::vk::detail
