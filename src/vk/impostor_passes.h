// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The impostor atlas's resolve and coverage passes and the GPU-driven path's impostors as Vulkan
// objects
// (si::gl's drawImpostorsIndirect): the impostor quads pass (impostor_quads.comp.glsl: each quad of
// the impostor bucket computed once, after the scatter pass) and the impostor draw that reads them
// (impostor.vert.glsl, SI_GPU_DRIVEN: shaded, or depth only), each with a set layout of its own
// (their clip table, atlas and quads bindings mean other things in the cull passes' and skinned
// draws' sets).

#include <vulkan/vulkan.h>

#include <vector>

#include "si/core/status.h"
#include "vk/gpu_driven_layout.h"
#include "vk/program_modules.h"
#include "vk/skinned_pipeline.h"

namespace si::vk::detail {

// The resolve pass's capture (its texture unit 0) and atlas level 0 (its image unit 0), shifted by
// the profile.
inline constexpr uint32_t kResolveCaptureBinding = 0 + kSamplerBindingShift;
inline constexpr uint32_t kResolveAtlasBinding = 0 + kImageBindingShift;

struct ImpostorPasses {
  ComputeLayout quads_layout;
  VkPipeline quads = VK_NULL_HANDLE;
  const ProgramModules* quads_program = nullptr;
  SkinnedLayout draw_layout;
  /// The atlas's sampler for the passes that fetch its texels: trilinear, clamped to the edges,
  /// no LOD bias (createAtlasSampler; the draws read each atlas through its own).
  VkSampler sampler = VK_NULL_HANDLE;
  /// The atlas's covered rectangles (impostor_coverage.comp.glsl): each level's extents, then
  /// the rectangles packed into the clip table.
  ComputeLayout coverage_layout;
  VkPipeline coverage[2] = {};
  const ProgramModules* coverage_programs[2] = {};
  /// The atlas's level 0 averaged from a supersampled capture (impostor_resolve.comp.glsl).
  ComputeLayout resolve_layout;
  VkPipeline resolve = VK_NULL_HANDLE;
  const ProgramModules* resolve_program = nullptr;
  /// Shaded, depth only.
  VkPipeline draws[2] = {};
  const ProgramModules* draw_programs[2] = {};
};

/// The quads pass's binding types: its storage blocks and its dynamic default block.
bool impostorQuadsBindingType(uint32_t binding, DescriptorKind kind, VkDescriptorType* type);
/// The coverage passes': the atlas, the extents and the clip table, the dynamic default block.
bool impostorCoverageBindingType(uint32_t binding, DescriptorKind kind, VkDescriptorType* type);
/// The resolve pass's: the capture, the atlas's level 0 as a storage image, the dynamic default
/// block.
bool impostorResolveBindingType(uint32_t binding, DescriptorKind kind, VkDescriptorType* type);

/// An impostor atlas's sampler as si::gl's ImpostorAtlas samples it: trilinear, clamped to the
/// edges, `lod_bias` added to the level (ImpostorDesc::lod_bias). kBackend on a failed call.
Status createAtlasSampler(VkDevice device, const VkAllocationCallbacks* allocator, float lod_bias,
                          VkSampler* out);

/// Makes `out`'s layouts and pipelines from the renderer's `programs` (vulkanPrograms() order):
/// the draws for rendering into `shaded` and `depth_only`. kBackend or kUnsupported naming what
/// failed (what was made stays in `out`, for destroyImpostorPasses).
Status createImpostorPasses(VkDevice device, const VkAllocationCallbacks* allocator,
                            const std::vector<ProgramModules>& programs,
                            const RenderingFormats& shaded, const RenderingFormats& depth_only,
                            ImpostorPasses* out);
void destroyImpostorPasses(VkDevice device, const VkAllocationCallbacks* allocator,
                           ImpostorPasses* passes);

}  // namespace si::vk::detail
