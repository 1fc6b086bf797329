// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "vk/vulkan_programs.h"

#include <vector>

namespace si::vk::detail {

namespace {

using si::detail::ProgramId;

constexpr VulkanKind kKinds[] = {VulkanKind::kShaded, VulkanKind::kDepthOnly, VulkanKind::kMotion};

// The catalog's program of `kind`, with the overlays on their masks or not, of drawCrowd's
// path or the GPU-driven one.
ProgramId catalogProgram(VulkanKind kind, bool layers, bool gpu_driven) {
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
ProgramId gpuSkinProgram(bool motion, bool layers) {
  if (motion) return layers ? ProgramId::kGpuSkinMotionLayers : ProgramId::kGpuSkinMotion;
  return layers ? ProgramId::kGpuSkinLayers : ProgramId::kGpuSkin;
}

std::vector<VulkanProgram> makePrograms() {
  std::vector<VulkanProgram> programs;
  for (bool gpu_driven : {false, true})
    for (bool morph : {false, true})
      for (bool layers : {false, true})
        for (bool eight : {false, true})
          for (bool words : {false, true})
            for (VulkanKind kind : kKinds) {
              if (words && kind == VulkanKind::kDepthOnly) continue;  // It reads no vertex words.
              std::string name = kind == VulkanKind::kShaded      ? "skinned"
                                 : kind == VulkanKind::kDepthOnly ? "depth_only"
                                                                  : "skinned_motion";
              if (gpu_driven) name = "gpu_" + name;
              if (layers) name += "_layers";
              if (morph) name += "_morph";
              if (eight) name += "_8";
              if (words) name += "_words";
              programs.push_back({catalogProgram(kind, layers, gpu_driven), kind, gpu_driven, false,
                                  false, false, false, layers, morph, eight, words, name});
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
    for (bool layers : {false, true})
      for (bool morph : {false, true})
        for (bool eight : {false, true})
          programs.push_back(
              {gpuSkinProgram(motion, layers), motion ? VulkanKind::kMotion : VulkanKind::kShaded,
               true, true, false, false, false, layers, morph, eight, false,
               std::string("gpu_skin") + (motion ? "_motion" : "") + (layers ? "_layers" : "") +
                   (morph ? "_morph" : "") + (eight ? "_8" : "")});
  for (const auto& [id, name] :
       {std::pair{ProgramId::kHizCopy, "hiz_copy"},
        std::pair{ProgramId::kHizCopyMultisample, "hiz_copy_ms"},
        std::pair{ProgramId::kHizReduce, "hiz_reduce"},
        std::pair{ProgramId::kImpostorQuads, "impostor_quads"},
        std::pair{ProgramId::kImpostorCoverage, "impostor_coverage"},
        std::pair{ProgramId::kImpostorCoverageRects, "impostor_coverage_rects"}})
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

size_t vulkanProgramIndex(VulkanKind kind, bool layers, const MeshVariant& mesh, bool gpu_driven) {
  const bool words = mesh.vertex_words && kind != VulkanKind::kDepthOnly;
  const std::vector<VulkanProgram>& programs = programList();
  for (size_t k = 0; k < programs.size(); ++k)
    if (!programs[k].compute && !programs[k].pulled && !programs[k].impostor &&
        programs[k].gpu_driven == gpu_driven && programs[k].kind == kind &&
        programs[k].layers == layers && programs[k].morph_targets == mesh.morph_targets &&
        programs[k].eight_influences == mesh.eight_influences && programs[k].vertex_words == words)
      return k;
  return 0;  // makePrograms() lists every combination.
}

size_t vulkanComputeProgramIndex(ProgramId id, const MeshVariant& mesh) {
  const bool skin = id == ProgramId::kGpuSkin || id == ProgramId::kGpuSkinMotion ||
                    id == ProgramId::kGpuSkinLayers || id == ProgramId::kGpuSkinMotionLayers;
  const std::vector<VulkanProgram>& programs = programList();
  for (size_t k = 0; k < programs.size(); ++k)
    if (programs[k].compute && programs[k].id == id &&
        (!skin || (programs[k].morph_targets == mesh.morph_targets &&
                   programs[k].eight_influences == mesh.eight_influences)))
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
