// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The Vulkan back-end's skinned program as a pipeline: the bindings si::gl's skinned program
// declares (shifted by the Vulkan profile), which the renderer fills; the descriptor set layout
// read from both stages' SPIR-V; and the graphics pipeline over a character's vertex stream.

#include <vulkan/vulkan.h>

#include <vector>

#include "si/core/shader_inputs.h"
#include "si/core/span.h"
#include "si/core/status.h"
#include "si_vk/vulkan_profile.h"
#include "vk/program_modules.h"
#include "vk/spirv_reflect.h"
#include "vk/vulkan_programs.h"

namespace si::vk::detail {

// The records' uniform block: 819 records of 80 bytes.
inline constexpr uint32_t kRecordsBinding = 0;
inline constexpr VkDeviceSize kRecordsRange = VkDeviceSize(kVulkanMaxInstances) * 80;
// The bindings si::gl's skinned program declares (its texture units and blocks, shifted by the
// profile), which the renderer fills; a module declaring another is refused by name.
inline constexpr uint32_t kPaletteInfoBinding = 4;
inline constexpr uint32_t kVertexMaterialsBinding = 10 + kStorageBindingShift;
inline constexpr uint32_t kMaterialTableBinding = 11 + kStorageBindingShift;
inline constexpr uint32_t kPaletteBinding = 0 + kSamplerBindingShift;
inline constexpr uint32_t kBaseColorBinding = 1 + kSamplerBindingShift;
inline constexpr uint32_t kCustomBinding = 2 + kSamplerBindingShift;
inline constexpr uint32_t kMaterialDataBinding = 4 + kSamplerBindingShift;
inline constexpr uint32_t kMorphBinding = 5 + kSamplerBindingShift;  // si_morph.glsl's si_morphs.
// The motion program's previous records and their indices (previous_index.glsl's storage
// binding 25): the whole record ring, read by 16-byte word from its start.
inline constexpr uint32_t kPreviousBinding = 25 + kStorageBindingShift;
// Layered animation (si_skinning.glsl's SI_LAYERS): each batch's layer records and previous
// layer records (uniform blocks of 819 uvec4), and the crowd's mask table (a storage block, at
// most kMaskRange bytes), all in the frame's region of the ring.
inline constexpr uint32_t kLayersBinding = 2;
inline constexpr uint32_t kPreviousLayersBinding = 3;
inline constexpr uint32_t kMaskBinding = 8 + kStorageBindingShift;
inline constexpr VkDeviceSize kLayersRange = VkDeviceSize(kVulkanMaxInstances) * 16;
inline constexpr VkDeviceSize kMaskRange = kRecordsRange;
// Impostors (impostor_quad.glsl, impostor.vert.glsl, impostor.frag.glsl): the atlas's clip table,
// the atlas, and the quads the GPU-driven impostor quads pass computed (a layout of their own:
// these bindings mean other things in the skinned draws' and the cull passes' sets).
inline constexpr uint32_t kImpostorClipsBinding = 9 + kStorageBindingShift;
inline constexpr uint32_t kImpostorAtlasBinding = 3 + kSamplerBindingShift;
inline constexpr uint32_t kImpostorQuadsBinding = 15 + kStorageBindingShift;
// Bytes of each default uniform block's binding: the vertex stage's camera, LOD and motion, the
// fragment stage's light and custom layers.
inline constexpr VkDeviceSize kDefaultsRange = 256;

/// The skinned program's descriptor set layout (binding order) and pipeline layout.
struct SkinnedLayout {
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  /// The dynamic buffers' bindings, in binding order: the order of a draw's dynamic offsets.
  std::vector<uint32_t> dynamic_bindings;
};

/// One shader stage's declarations.
struct StageReflection {
  VkShaderStageFlags stage;
  const SpirvReflection* reflection;
};

/// The union of `stages`' descriptors (the shaded and depth-only programs' stages; the records
/// and the default blocks dynamic: their offsets move per batch and frame) as a set layout and a
/// pipeline layout of that one set. kUnsupported naming a descriptor at a binding the renderer
/// does not fill; kBackend on a failed call.
Status createSkinnedLayout(VkDevice device, const VkAllocationCallbacks* allocator,
                           Span<const StageReflection> stages, SkinnedLayout* out);

/// The formats a pipeline renders into (VkPipelineRenderingCreateInfo's) and their samples: no
/// colour attachment when `color` is VK_FORMAT_UNDEFINED (depth only); motion vectors as
/// attachment 1 when `motion` is not.
struct RenderingFormats {
  VkFormat color = VK_FORMAT_UNDEFINED;
  VkFormat depth = VK_FORMAT_UNDEFINED;
  VkFormat motion = VK_FORMAT_UNDEFINED;
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;  ///< Of every attachment.
  /// Colour attachments of format `color` (without motion): the impostor capture writes 3.
  uint32_t color_count = 1;
};

/// An impostor program's graphics pipeline for dynamic rendering into `formats`: no vertex input
/// (a quad per instance: 4 vertices of a triangle strip, from gl_VertexID and gl_InstanceID),
/// both faces drawn, the fragment stage also for depth only (its coverage test discards); the
/// rest as createSkinnedPipeline's. kBackend on a failed call.
Status createImpostorPipeline(VkDevice device, const VkAllocationCallbacks* allocator,
                              const ProgramModules& program, VkPipelineLayout pipeline_layout,
                              RenderingFormats formats, VkPipeline* out);

/// A skinned program's graphics pipeline for `stream`'s vertex format (as si::gl's
/// CharacterBuffers describes it: an attribute for each input the vertex stage reads; a
/// GPU-driven draw's entry index from vertex binding 1, per instance), for
/// dynamic rendering into `formats`: back faces culled, depth tested and written; the viewport,
/// scissor, depth compare, front face and depth bias dynamic (set by each draw). kUnsupported
/// naming a vertex input the stream has no word for; kBackend on a failed call.
Status createSkinnedPipeline(VkDevice device, const VkAllocationCallbacks* allocator,
                             const ProgramModules& program, VkPipelineLayout pipeline_layout,
                             RenderingFormats formats, const VertexStream& stream, VkPipeline* out);

}  // namespace si::vk::detail
