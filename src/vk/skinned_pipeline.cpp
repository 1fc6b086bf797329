// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The skinned program's layouts and pipeline.
#include "vk/skinned_pipeline.h"

#include <algorithm>
#include <iterator>
#include <map>
#include <vector>

#include "core/str_cat.h"
#include "vk/device_objects.h"
#include "vk/gpu_driven_layout.h"

namespace si::vk::detail {

using si::detail::strCat;

Status createSkinnedLayout(VkDevice device, const VkAllocationCallbacks* allocator,
                           Span<const StageReflection> stages, SkinnedLayout* out) {
  // The union of the stages' descriptors: the records and default blocks dynamic (their
  // offsets move per batch and frame), every other binding one the renderer fills.
  std::map<uint32_t, VkDescriptorSetLayoutBinding> bindings;
  for (const StageReflection& r : stages) {
    const VkShaderStageFlags stage = r.stage;
    for (const SpirvDescriptor& d : r.reflection->descriptors) {
      const uint32_t b = d.binding;
      VkDescriptorType type;
      if (b == kRecordsBinding || b == kVertexDefaultsBinding || b == kFragmentDefaultsBinding ||
          b == kLayersBinding || b == kPreviousLayersBinding)
        type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
      else if (b == kMaskBinding)
        type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC;
      else if (b == kPaletteInfoBinding)
        type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
      else if (b == kVertexMaterialsBinding || b == kMaterialTableBinding ||
               b == kPreviousBinding || b == kDrivenRecordsBinding || b == kDrivenEntriesBinding ||
               b == kDrivenVisibleBinding || b == kEntryDataBinding || b == kRingBinding ||
               b == kSourceBinding || b == kLodVerticesBinding || b == kTangentRingBinding ||
               b == kPreviousOutBinding || b == kPreviousRingBinding || b == kLayersOutBinding ||
               b == kPreviousLayersOutBinding || b == kDrivenMaskBinding ||
               b == kComposeTableBinding || b == kComposedRowsBinding ||
               b == kComposedPreviousRowsBinding || b == kImpostorClipsBinding ||
               b == kImpostorQuadsBinding)
        type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      else if (b == kPaletteBinding || b == kBaseColorBinding || b == kCustomBinding ||
               b == kMaterialDataBinding || b == kMorphBinding || b == kImpostorAtlasBinding)
        type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
      else
        return {StatusCode::kUnsupported,
                strCat("the skinned program's ", descriptorKindName(d.kind), " '", d.name,
                       "' at binding ", b, " is one the Vulkan renderer does not fill")};
      auto [it, added] =
          bindings.emplace(b, VkDescriptorSetLayoutBinding{b, type, 1, stage, nullptr});
      if (!added) it->second.stageFlags |= stage;
    }
  }
  out->bindings.clear();
  out->dynamic_bindings.clear();
  for (const auto& [b, binding] : bindings) {
    out->bindings.push_back(binding);
    if (binding.descriptorType == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC ||
        binding.descriptorType == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC)
      out->dynamic_bindings.push_back(b);
  }
  return createSetLayouts(device, allocator, out->bindings, &out->set_layout,
                          &out->pipeline_layout);
}

namespace {

// A skinned program's pipeline over `stream`, or (null) an impostor program's.
Status createPipeline(VkDevice device, const VkAllocationCallbacks* allocator,
                      const ProgramModules& program, VkPipelineLayout pipeline_layout,
                      RenderingFormats formats, const VertexStream* vertex_stream,
                      VkPipeline* out) {
  const bool color = formats.color != VK_FORMAT_UNDEFINED;
  const bool quads = vertex_stream == nullptr;
  const VertexStream stream = quads ? VertexStream() : *vertex_stream;
  VkPipelineShaderStageCreateInfo stages[2] = {
      vkStruct<VkPipelineShaderStageCreateInfo>(
          VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO),
      vkStruct<VkPipelineShaderStageCreateInfo>(
          VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO)};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = program.vertex_module;
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = program.fragment_module;
  stages[1].pName = "main";
  // The vertex stream as si::gl's CharacterBuffers describes it (shader_inputs.h): each input
  // the vertex stage reads. Without tangents, attribute 7 reads the normal's word (w 0: no
  // tangent frame); without texture coordinates 1 or colours, attributes 8 and 9 read other
  // words, which the fragment stage does not use (SiMaterial.layer.w says what the mesh has).
  // The GPU-driven draw's entry index (a_entry, location 5): binding 1, per instance, from an
  // identity buffer (firstInstance + instance: the bucket's entries).
  const VkVertexInputBindingDescription bindings[2] = {
      {0, stream.stride_bytes, VK_VERTEX_INPUT_RATE_VERTEX}, {1, 4, VK_VERTEX_INPUT_RATE_INSTANCE}};
  const VkFormat joints =
      stream.wide_joints ? VK_FORMAT_R16G16B16A16_UINT : VK_FORMAT_R8G8B8A8_UINT;
  const auto word = [](uint32_t offset, uint32_t otherwise) {
    return offset != 0 ? offset : otherwise;
  };
  const VkVertexInputAttributeDescription known[] = {
      {0, 0, VK_FORMAT_R32G32B32_SFLOAT, VertexStream::kPositionOffset},
      {1, 0, VK_FORMAT_A2B10G10R10_SNORM_PACK32, VertexStream::kNormalOffset},
      {2, 0, VK_FORMAT_R16G16_SFLOAT, VertexStream::kTexcoordOffset},
      {3, 0, joints, VertexStream::kJointsOffset},
      {4, 0, VK_FORMAT_R16G16B16A16_UNORM, stream.weights_offset},
      {7, 0, VK_FORMAT_A2B10G10R10_SNORM_PACK32,
       word(stream.tangent_offset, VertexStream::kNormalOffset)},
      {8, 0, VK_FORMAT_R16G16_SFLOAT, word(stream.texcoord1_offset, VertexStream::kTexcoordOffset)},
      {9, 0, VK_FORMAT_R8G8B8A8_UNORM, word(stream.color_offset, VertexStream::kNormalOffset)},
      {10, 0, joints, stream.joints1_offset},
      {11, 0, VK_FORMAT_R16G16B16A16_UNORM, stream.weights1_offset},
      {12, 0, VK_FORMAT_R32_UINT, stream.morph_offset},  // The morph word.
      {5, 1, VK_FORMAT_R32_UINT, 0},                     // The GPU-driven draw's entry.
  };
  std::vector<VkVertexInputAttributeDescription> attributes;
  for (const SpirvVarying& in :
       quads ? std::vector<SpirvVarying>() : program.vertex_reflection.inputs) {
    const VkVertexInputAttributeDescription* a = nullptr;
    for (const VkVertexInputAttributeDescription& k : known)
      if (k.location == in.location) a = &k;
    // Influences 5 to 8 and the morph word only where the mesh has them (the program is the
    // mesh's variant).
    if (a == nullptr || ((in.location == 10 || in.location == 11) && stream.joints1_offset == 0) ||
        (in.location == 12 && stream.morph_offset == 0))
      return {StatusCode::kUnsupported,
              strCat("the vertex stage reads '", in.name, "' at location ", in.location,
                     ", for which the character's vertex stream has no word")};
    attributes.push_back(*a);
  }
  const bool entries =
      std::any_of(attributes.begin(), attributes.end(),
                  [](const VkVertexInputAttributeDescription& a) { return a.binding == 1; });
  auto input = vkStruct<VkPipelineVertexInputStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO);
  input.vertexBindingDescriptionCount = quads ? 0 : entries ? 2 : 1;
  input.pVertexBindingDescriptions = bindings;
  input.vertexAttributeDescriptionCount = uint32_t(attributes.size());
  input.pVertexAttributeDescriptions = attributes.data();
  auto assembly = vkStruct<VkPipelineInputAssemblyStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO);
  assembly.topology =
      quads ? VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP : VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  auto viewport = vkStruct<VkPipelineViewportStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO);
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  auto raster = vkStruct<VkPipelineRasterizationStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO);
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = quads ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;  // Dynamic: each draw sets it.
  raster.lineWidth = 1.0f;
  auto multisample = vkStruct<VkPipelineMultisampleStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
  multisample.rasterizationSamples = formats.samples;
  auto depth = vkStruct<VkPipelineDepthStencilStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
  depth.depthTestEnable = VK_TRUE;
  depth.depthWriteEnable = VK_TRUE;
  depth.depthCompareOp = VK_COMPARE_OP_LESS;  // Dynamic: each draw sets it.
  const bool motion = color && formats.motion != VK_FORMAT_UNDEFINED;
  VkPipelineColorBlendAttachmentState attachments[3] = {};
  attachments[0].colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                  VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  // Identical (without the independentBlend feature); the motion format's missing channels
  // are not written.
  attachments[1] = attachments[2] = attachments[0];
  const uint32_t colors = !color ? 0 : motion ? 2 : std::min<uint32_t>(formats.color_count, 3);
  auto blend = vkStruct<VkPipelineColorBlendStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
  blend.attachmentCount = colors;
  blend.pAttachments = attachments;
  // Core in Vulkan 1.3 (extended dynamic state 1 and 2).
  const VkDynamicState dynamic_states[] = {
      VK_DYNAMIC_STATE_VIEWPORT,   VK_DYNAMIC_STATE_SCISSOR,    VK_DYNAMIC_STATE_DEPTH_COMPARE_OP,
      VK_DYNAMIC_STATE_FRONT_FACE, VK_DYNAMIC_STATE_DEPTH_BIAS, VK_DYNAMIC_STATE_DEPTH_BIAS_ENABLE};
  auto dynamic = vkStruct<VkPipelineDynamicStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO);
  dynamic.dynamicStateCount = uint32_t(std::size(dynamic_states));
  dynamic.pDynamicStates = dynamic_states;
  auto rendering =
      vkStruct<VkPipelineRenderingCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO);
  const VkFormat color_formats[3] = {formats.color, motion ? formats.motion : formats.color,
                                     formats.color};
  rendering.colorAttachmentCount = colors;
  rendering.pColorAttachmentFormats = colors > 0 ? color_formats : nullptr;
  rendering.depthAttachmentFormat = formats.depth;
  auto info =
      vkStruct<VkGraphicsPipelineCreateInfo>(VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO);
  info.pNext = &rendering;
  // Depth only: no fragment stage (the program's is empty), so nothing reads the varyings.
  info.stageCount = color || quads ? 2 : 1;
  info.pStages = stages;
  info.pVertexInputState = &input;
  info.pInputAssemblyState = &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = pipeline_layout;
  return checkVk(vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &info, allocator, out),
                 "vkCreateGraphicsPipelines");
}

}  // namespace

Status createSkinnedPipeline(VkDevice device, const VkAllocationCallbacks* allocator,
                             const ProgramModules& program, VkPipelineLayout pipeline_layout,
                             RenderingFormats formats, const VertexStream& stream,
                             VkPipeline* out) {
  return createPipeline(device, allocator, program, pipeline_layout, formats, &stream, out);
}

Status createImpostorPipeline(VkDevice device, const VkAllocationCallbacks* allocator,
                              const ProgramModules& program, VkPipelineLayout pipeline_layout,
                              RenderingFormats formats, VkPipeline* out) {
  return createPipeline(device, allocator, program, pipeline_layout, formats, nullptr, out);
}

}  // namespace si::vk::detail
