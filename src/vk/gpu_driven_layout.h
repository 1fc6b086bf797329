// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The GPU-driven path's compute passes as Vulkan objects: the bindings si::gl's cull, commands,
// scatter and pre-skinning passes declare (shaders/cull*.comp.glsl, gpu_skin.comp.glsl, shifted
// by the Vulkan profile), the one set layout of them read from their SPIR-V, and a pass's
// compute pipeline. What the draw
// reads of the passes' output (records, entries, visible list) is at the bindings below in the
// GPU-driven draw programs' set (skinned_pipeline.h).

#include <vulkan/vulkan.h>

#include <vector>

#include "si/core/span.h"
#include "si/core/status.h"
#include "si_vk/vulkan_profile.h"
#include "vk/program_modules.h"
#include "vk/spirv_reflect.h"
#include "vk/vulkan_programs.h"

namespace si::vk::detail {

// The passes' storage blocks (cull_common.glsl, cull.comp.glsl ...), by their OpenGL binding.
inline constexpr uint32_t kStateBinding = 0 + kStorageBindingShift;
inline constexpr uint32_t kClipsBinding = 1 + kStorageBindingShift;
inline constexpr uint32_t kTimesBinding = 2 + kStorageBindingShift;
inline constexpr uint32_t kCountersBinding = 3 + kStorageBindingShift;
inline constexpr uint32_t kDrivenRecordsBinding = 4 + kStorageBindingShift;
inline constexpr uint32_t kDrivenEntriesBinding = 5 + kStorageBindingShift;
inline constexpr uint32_t kDrivenVisibleBinding = 6 + kStorageBindingShift;
inline constexpr uint32_t kCommandsBinding = 7 + kStorageBindingShift;
inline constexpr uint32_t kRangesBinding = 8 + kStorageBindingShift;
inline constexpr uint32_t kBucketInfoBinding = 9 + kStorageBindingShift;
inline constexpr uint32_t kEntryDataBinding = 12 + kStorageBindingShift;
inline constexpr uint32_t kViewLodsBinding = 16 + kStorageBindingShift;
// Pre-skinning (gpu_skin.comp.glsl, pulled.vert.glsl): the ring of pre-skinned vertices, the
// character's vertex stream read as words, its vertex lists, the tangent ring.
inline constexpr uint32_t kRingBinding = 13 + kStorageBindingShift;
inline constexpr uint32_t kSourceBinding = 14 + kStorageBindingShift;
inline constexpr uint32_t kLodVerticesBinding = 15 + kStorageBindingShift;
inline constexpr uint32_t kTangentRingBinding = 28 + kStorageBindingShift;
// Layered animation: the crowd's overlays (the cull pass reads them), each visible instance's
// layer record and previous layer record (the cull pass writes them, the pre-skinning pass and
// the draws read them), and the crowd's layer mask table (si::layerMaskTable; at
// kDrivenMaskStorageBinding in the GPU-driven programs, vulkan_programs.h).
inline constexpr uint32_t kOverlaysBinding = 17 + kStorageBindingShift;
inline constexpr uint32_t kLayersOutBinding = 18 + kStorageBindingShift;
inline constexpr uint32_t kPreviousLayersOutBinding = 21 + kStorageBindingShift;
inline constexpr uint32_t kDrivenMaskBinding = kDrivenMaskStorageBinding + kStorageBindingShift;
// Composed layers (2D blends): the crowd's compose table (si::detail::layerComposeTable), and
// the rows the layer compose pass writes per visible instance, and its previous ones (motion
// vectors), which the pre-skinning pass and the draws read (layer_compose.glsl).
inline constexpr uint32_t kComposeTableBinding = 23 + kStorageBindingShift;
inline constexpr uint32_t kComposedRowsBinding = 26 + kStorageBindingShift;
inline constexpr uint32_t kComposedPreviousRowsBinding = 27 + kStorageBindingShift;
// Motion vectors: a view's drawn records (two parities: the frame's, the previous one's), each
// visible instance's previous record (read by the motion draws), and the previous positions'
// ring (the pre-skinning pass writes it, the pulled motion draw reads it).
inline constexpr uint32_t kDrawnBinding = 19 + kStorageBindingShift;
inline constexpr uint32_t kPreviousOutBinding = 20 + kStorageBindingShift;
inline constexpr uint32_t kPreviousRingBinding = 22 + kStorageBindingShift;
// Live poses: declared by the cull pass, not drawn by the Vulkan back-end's GPU-driven path yet
// (no posed instance): bound to a placeholder the pass never reads.
inline constexpr uint32_t kLivePosesBinding = 25 + kStorageBindingShift;
// Occlusion culling's depth pyramid (cull_occlusion.glsl's u_hiz): a placeholder until built.
inline constexpr uint32_t kPyramidBinding = 1 + kSamplerBindingShift;
// Bytes of a pass's default uniform block (the cull pass's is 592).
inline constexpr VkDeviceSize kComputeDefaultsRange = 1024;

/// The passes' set layout and pipeline layout.
struct ComputeLayout {
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
  std::vector<VkDescriptorSetLayoutBinding> bindings;
};

/// The descriptor type the renderer gives a compute pass's descriptor of `kind` at `binding`;
/// false for one it does not fill.
using ComputeBindingType = bool (*)(uint32_t binding, DescriptorKind kind, VkDescriptorType* type);
/// The GPU-driven passes' (cull, commands, scatter, pre-skinning): their storage blocks, the
/// palette's information block, the pyramid, palette and morph samplers; the default block
/// dynamic (each pass's at its own offset).
bool drivenPassBindingType(uint32_t binding, DescriptorKind kind, VkDescriptorType* type);

/// The union of `passes`' descriptors (their compute stages) as one set layout, each typed by
/// `type_of`, and a pipeline layout of it. kUnsupported naming a descriptor `type_of` does not
/// fill (`what`: whose passes); kBackend on a failed call.
Status createComputeLayout(VkDevice device, const VkAllocationCallbacks* allocator,
                           Span<const ProgramModules* const> passes, ComputeBindingType type_of,
                           const char* what, ComputeLayout* out);
/// Destroys what createComputeLayout made.
void destroyComputeLayout(VkDevice device, const VkAllocationCallbacks* allocator,
                          ComputeLayout* layout);

/// `pass`'s compute pipeline on `layout`. kBackend naming the failed call.
Status createComputePipeline(VkDevice device, const VkAllocationCallbacks* allocator,
                             const ProgramModules& pass, VkPipelineLayout layout, VkPipeline* out);

}  // namespace si::vk::detail
