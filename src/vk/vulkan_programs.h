// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The Vulkan back-end's programs: which programs of si::gl's catalog it builds, in which
// variants (the crowd's layers; the character's mesh: morph targets, 8 influences, optional
// vertex words), and
// the shader
// configuration each is assembled with (the same files, defines and catalog; glslang defines
// VULKAN, which si_profile.glsl reads). Used at build time by the step that writes their GLSL
// (tools/write_vulkan_glsl.cpp) and at run time to name the embedded SPIR-V. No Vulkan here.

#include <cstddef>
#include <string>

#include "gl/programs/program_catalog.h"
#include "si/core/span.h"

namespace si::vk::detail {

/// What a program draws (vk::DrawMode, and shaded with motion vectors).
enum class VulkanKind : uint8_t { kShaded = 0, kDepthOnly, kMotion };
inline constexpr size_t kVulkanKinds = 3;

/// One program of the back-end: the catalog's program, the variant it is assembled for (layered
/// animation: the overlays on their masks; ShaderConfig::morph_targets, eight_influences,
/// vertex_words) and the name its SPIR-V files take: "skinned", "depth_only" or
/// "skinned_motion", then "_layers", "_morph", "_8", "_words" for each variant it is
/// (src/vk/CMakeLists.txt makes the same list).
struct VulkanProgram {
  si::detail::ProgramId id;
  VulkanKind kind;
  /// The GPU-driven path's draw (records through the cull pass's bucket entries: "gpu_" before
  /// the name), or one of its compute passes (compute; kind kShaded, no variant).
  bool gpu_driven;
  bool compute;
  /// The GPU-driven path's pre-skinned draw (vertex pulling from the ring: "gpu_pulled"), with
  /// the tangent ring read (`tangents`) for a character with tangents.
  bool pulled;
  bool tangents;
  /// The impostor atlas's capture (kImpostorCapture: "impostor_capture", per mesh variant) or
  /// the GPU-driven impostor draw (kGpuDrivenImpostor, "gpu_impostor", and its depth-only
  /// variant).
  bool impostor;
  bool layers;
  bool morph_targets;
  bool eight_influences;
  bool vertex_words;
  std::string name;
  /// With `layers`, on the GPU-driven path: the skinning reads the rows the layer compose pass
  /// composed ("_composed" in place of "_layers": 2D blends need them), or the compose pass itself
  /// (kGpuLayerCompose, kGpuLayerComposeMotion: "gpu_layer_compose", per morph variant).
  bool composed = false;
};

/// The programs the Vulkan back-end builds so far: the vertex-shader path, shaded, depth only
/// and shaded with motion vectors, each without and with layers, for meshes without and with
/// morph targets, of 4 and of 8 influences, the shaded ones also for meshes with vertex words
/// (the depth-only stage reads none), ordered by morph targets, layers, 8 influences, vertex
/// words, then kind; then the GPU-driven path's draws, shaded, depth only and with motion
/// vectors, without layers, with layers and with composed layers ("_composed"), for the same
/// meshes in the same order; its pre-skinned draws
/// ("gpu_pulled", "_tangents", "_words"; "gpu_pulled_depth_only"; "gpu_pulled_motion",
/// "_tangents", "_words"); then its compute passes: "cull", "cull_commands", "cull_scatter",
/// the pre-skinning pass for each mesh ("gpu_skin", "_morph", "_8"), with the previous
/// positions ("gpu_skin_motion", ...), each without layers, with layers and with composed
/// layers ("gpu_skin_layers", "gpu_skin_composed", "gpu_skin_motion_layers", ...), the layer
/// compose pass for meshes without and with morph targets ("gpu_layer_compose", "_motion",
/// "_morph"), occlusion culling's depth pyramid passes
/// ("hiz_copy", "hiz_copy_ms", "hiz_reduce"), the impostor quads pass ("impostor_quads") and the
/// impostor atlas's covered rectangles ("impostor_coverage", "impostor_coverage_rects") and its
/// level 0 averaged from a supersampled capture ("impostor_resolve").
/// Between the pre-skinned draws and the compute passes: the impostor atlas's capture for each
/// mesh ("impostor_capture", "_morph", "_8", "_words") and the GPU-driven impostor draws
/// ("gpu_impostor", "gpu_impostor_depth_only").
Span<const VulkanProgram> vulkanPrograms();

/// What a character's mesh needs of its programs.
struct MeshVariant {
  bool morph_targets = false;
  bool eight_influences = false;
  bool vertex_words = false;
};

/// The index in vulkanPrograms() of the program of `kind`, with layers or not, for a mesh of
/// `mesh` (its vertex words ignored for kDepthOnly); the GPU-driven path's draw with
/// `gpu_driven`, reading the compose pass's rows with `composed` (GPU-driven, with layers).
size_t vulkanProgramIndex(VulkanKind kind, bool layers, const MeshVariant& mesh,
                          bool gpu_driven = false, bool composed = false);
/// The index in vulkanPrograms() of the GPU-driven compute pass `id` (kCull, kCullCommands,
/// kCullScatter, kHizCopy, kHizCopyMultisample, kHizReduce, kImpostorQuads, kImpostorCoverage,
/// kImpostorCoverageRects, kImpostorResolve; the pre-skinning passes kGpuSkin, kGpuSkinMotion and
/// their Layers and Composed variants, and the compose passes kGpuLayerCompose and
/// kGpuLayerComposeMotion, for a mesh of `mesh`).
size_t vulkanComputeProgramIndex(si::detail::ProgramId id, const MeshVariant& mesh = {});
/// The index in vulkanPrograms() of the impostor capture for a mesh of `mesh`.
size_t vulkanCaptureProgramIndex(const MeshVariant& mesh);
/// The index in vulkanPrograms() of the GPU-driven impostor draw, shaded or depth only.
size_t vulkanImpostorProgramIndex(bool depth_only);
/// The index in vulkanPrograms() of the GPU-driven pre-skinned draw of `kind` (kShaded, kMotion or
/// kDepthOnly) for a character with tangents or not and a mesh of `mesh` (its vertex words).
size_t vulkanPulledProgramIndex(VulkanKind kind, bool tangents, const MeshVariant& mesh);

/// The layer mask table's storage binding (OpenGL's numbering, before the Vulkan profile's
/// shift) in the GPU-driven programs, draws and passes: one set holds every pass's resources, and
/// 8, the table's binding elsewhere, holds the bucket ranges there.
inline constexpr uint32_t kDrivenMaskStorageBinding = 31;

/// Records in the instance uniform block: 819 of 80 bytes fill a 64 KiB block, the
/// maxUniformBufferRange of NVIDIA's and lavapipe's drivers (the Vulkan minimum is 16 KiB: a
/// device below 64 KiB is refused by name).
inline constexpr uint32_t kVulkanMaxInstances = 819;

/// The configuration `program` is assembled with.
si::detail::ShaderConfig vulkanShaderConfig(const VulkanProgram& program);

}  // namespace si::vk::detail
