// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The Vulkan back-end: its init, characters, uploads and frames. The instanced path's draw:
// renderer_instanced.cpp; the GPU-driven path's entry points: renderer_gpu_driven.cpp.
#include "si/vk/renderer.h"

#include "vk/renderer_impl.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <vector>

#include "core/str_cat.h"
#include "si/core/shader_inputs.h"
#include "si_vk/vulkan_profile.h"
#include "vk/character_resources.h"
#include "vk/character_set.h"
#include "vk/device_objects.h"
#include "vk/gpu_driven_layout.h"
#include "vk/gpu_driven_views.h"
#include "vk/image_upload.h"
#include "vk/program_modules.h"
#include "vk/skinned_pipeline.h"
#include "vk/spirv_reflect.h"
#include "vk/vulkan_programs.h"

namespace si::vk {

using si::detail::strCat;
using namespace si::vk::detail;

Renderer::Renderer() = default;
Renderer::~Renderer() {
  shutdown();
}

Status Renderer::init(const RendererDesc& desc) {
  shutdown();
  if (desc.physical_device == VK_NULL_HANDLE || desc.device == VK_NULL_HANDLE)
    return {StatusCode::kInvalidArgument, "vk::Renderer::init: no physical device or device"};
  if (!(desc.morph_lod_share >= 0.0f && desc.morph_lod_share <= 1.0f))
    return {StatusCode::kInvalidArgument, strCat("vk::Renderer::init: morph_lod_share ",
                                                 desc.morph_lod_share, " is outside 0 to 1")};
  if (desc.frames_in_flight < 1 || desc.frames_in_flight > 8)
    return {StatusCode::kInvalidArgument, strCat("vk::Renderer::init: frames_in_flight ",
                                                 desc.frames_in_flight, " is outside 1 to 8")};
  if (desc.ring_bytes_per_frame < kRecordsRange)
    return {StatusCode::kInvalidArgument,
            strCat("vk::Renderer::init: ring_bytes_per_frame ", desc.ring_bytes_per_frame,
                   " holds less than one batch (", kRecordsRange, " bytes)")};
  // Dynamic offsets are 32-bit: every slot's region, and a batch past its end, below 4 GiB.
  const VkDeviceSize slot_bytes = alignUp(desc.ring_bytes_per_frame, 256);
  if (uint64_t(desc.frames_in_flight) * slot_bytes + kRecordsRange > UINT32_MAX)
    return {StatusCode::kLimitExceeded,
            strCat("vk::Renderer::init: a ring of ", desc.frames_in_flight, " x ",
                   desc.ring_bytes_per_frame, " bytes passes the 4 GiB of a dynamic offset")};
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(desc.physical_device, &props);
  if (props.apiVersion < VK_API_VERSION_1_3)
    return {StatusCode::kUnsupported, "vk::Renderer::init: the device is below Vulkan 1.3"};
  if (props.limits.maxUniformBufferRange < kRecordsRange)
    return {StatusCode::kUnsupported,
            strCat("vk::Renderer::init: maxUniformBufferRange ", props.limits.maxUniformBufferRange,
                   " is below a batch's ", kRecordsRange, " bytes of records")};
  auto f13 = vkStruct<VkPhysicalDeviceVulkan13Features>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES);
  auto features = vkStruct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
  features.pNext = &f13;
  vkGetPhysicalDeviceFeatures2(desc.physical_device, &features);
  if (!f13.dynamicRendering)
    return {StatusCode::kUnsupported, "vk::Renderer::init: the device has no dynamic rendering"};
  if (desc.gpu_driven) {
    const VkPhysicalDeviceFeatures& f = features.features;
    for (const auto& [has, name] :
         {std::pair{f.shaderFloat64, "shaderFloat64"},
          std::pair{f.multiDrawIndirect, "multiDrawIndirect"},
          std::pair{f.drawIndirectFirstInstance, "drawIndirectFirstInstance"}})
      if (!has)
        return {StatusCode::kUnsupported,
                strCat("vk::Renderer::init: the GPU-driven path needs the device feature ", name)};
  }
  const auto renderable = [](VkSampleCountFlagBits samples, VkSampleCountFlags counts) {
    const uint32_t n = uint32_t(samples);
    return n != 0 && n <= 64 && (n & (n - 1)) == 0 && (counts & n) != 0;
  };
  const VkPhysicalDeviceLimits& limits = props.limits;
  if (!renderable(desc.samples,
                  limits.framebufferColorSampleCounts & limits.framebufferDepthSampleCounts) ||
      !renderable(desc.depth_only_samples, limits.framebufferDepthSampleCounts))
    return {StatusCode::kUnsupported,
            strCat("vk::Renderer::init: samples ", uint32_t(desc.samples),
                   " (colour and depth) or ", uint32_t(desc.depth_only_samples),
                   " (depth only) is no count the device renders (colour ",
                   limits.framebufferColorSampleCounts, ", depth ",
                   limits.framebufferDepthSampleCounts, ")")};
  VkFormatProperties normal{};
  vkGetPhysicalDeviceFormatProperties(desc.physical_device, VK_FORMAT_A2B10G10R10_SNORM_PACK32,
                                      &normal);
  if ((normal.bufferFeatures & VK_FORMAT_FEATURE_VERTEX_BUFFER_BIT) == 0)
    return {StatusCode::kUnsupported,
            "vk::Renderer::init: the device reads no VK_FORMAT_A2B10G10R10_SNORM_PACK32 vertex "
            "attribute (the vertex stream's normals)"};
  if (desc.motion_format != VK_FORMAT_UNDEFINED) {
    VkFormatProperties motion{};
    vkGetPhysicalDeviceFormatProperties(desc.physical_device, desc.motion_format, &motion);
    if ((motion.optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT) == 0)
      return {StatusCode::kUnsupported,
              strCat("vk::Renderer::init: motion_format ", int(desc.motion_format),
                     " is no colour attachment format of the device")};
    // The motion program reads the previous records from the whole ring as a storage buffer.
    const uint64_t ring = uint64_t(desc.frames_in_flight) * slot_bytes + kRecordsRange;
    if (ring > props.limits.maxStorageBufferRange)
      return {StatusCode::kLimitExceeded,
              strCat("vk::Renderer::init: with motion vectors the record ring (", ring,
                     " bytes) is read as one storage buffer, past maxStorageBufferRange ",
                     props.limits.maxStorageBufferRange)};
  }
  auto impl = std::make_unique<Impl>();
  impl->desc = desc;
  impl->objects.init(desc.physical_device, desc.device, desc.allocator);
  impl->ubo_alignment = std::max<VkDeviceSize>(props.limits.minUniformBufferOffsetAlignment, 16);
  impl->storage_alignment =
      std::max<VkDeviceSize>(props.limits.minStorageBufferOffsetAlignment, 16);
  impl->max_image_size = props.limits.maxImageDimension2D;
  impl->max_framebuffer_size =
      std::min(props.limits.maxFramebufferWidth, props.limits.maxFramebufferHeight);
  impl->max_viewport_size =
      std::min(props.limits.maxViewportDimensions[0], props.limits.maxViewportDimensions[1]);
  impl->slot_bytes = slot_bytes;
  impl_ = std::move(impl);
  Impl& m = *impl_;
  Status s = Status::ok();
  m.programs.resize(vulkanPrograms().size());
  for (size_t k = 0; k < m.programs.size() && s.isOk(); ++k) {
    const VulkanProgram& p = vulkanPrograms()[k];
    if (p.gpu_driven && !desc.gpu_driven) continue;
    s = loadProgramModules(m.device(), m.allocator(), p.name.c_str(), p.compute,
                           p.compute ? kComputeDefaultsRange : kDefaultsRange, &m.programs[k]);
  }
  if (s.isOk()) {
    std::vector<StageReflection> stages;
    for (size_t k = 0; k < m.programs.size(); ++k) {
      if (vulkanPrograms()[k].gpu_driven) continue;
      const ProgramModules& p = m.programs[k];
      stages.push_back({VK_SHADER_STAGE_VERTEX_BIT, &p.vertex_reflection});
      stages.push_back({VK_SHADER_STAGE_FRAGMENT_BIT, &p.fragment_reflection});
    }
    s = createSkinnedLayout(m.device(), m.allocator(),
                            Span<const StageReflection>(stages.data(), stages.size()), &m.layout);
  }
  if (s.isOk() && m.layout.dynamic_bindings.size() > Impl::kMaxDynamicBindings)
    s = {
        StatusCode::kUnsupported,
        strCat("vk::Renderer::init: the programs declare ", m.layout.dynamic_bindings.size(),
               " dynamic buffers, more than the ", Impl::kMaxDynamicBindings, " the draws offset")};
  for (const auto& [filter, out] :
       {std::pair{VK_FILTER_NEAREST, &m.nearest}, std::pair{VK_FILTER_LINEAR, &m.linear}}) {
    if (!s.isOk()) break;
    auto info = vkStruct<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
    info.magFilter = info.minFilter = filter;
    info.mipmapMode =
        filter == VK_FILTER_LINEAR ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST;
    // OpenGL's default wrap for the materials; the palette is read with texelFetch.
    info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    info.maxLod = VK_LOD_CLAMP_NONE;
    s = checkVk(vkCreateSampler(m.device(), &info, m.allocator(), out), "vkCreateSampler");
  }
  if (s.isOk())
    s = m.objects.createBuffer(
        VkDeviceSize(desc.frames_in_flight) * m.slot_bytes + kRecordsRange,
        VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true,
        "the record ring", &m.ring);
  if (s.isOk())
    s = m.objects.createImage(1, 1, 1, 1, VK_FORMAT_R8G8B8A8_UNORM, true,
                              "the custom texture's placeholder", &m.custom);
  if (s.isOk())
    s = m.objects.createImage(1, 1, 1, 1, VK_FORMAT_R32G32B32A32_UINT, false,
                              "the morph image's placeholder", &m.no_morphs);
  if (s.isOk())
    s = m.objects.createBuffer(48, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true,
                               "the placeholders' staging", &m.placeholder_staging);
  if (s.isOk()) {
    std::memset(m.placeholder_staging.mapped, 0, 48);
    std::memset(m.placeholder_staging.mapped, 255, 4);
  }
  if (s.isOk() && desc.gpu_driven) s = m.initGpuDriven(props.limits);
  if (!s.isOk()) shutdown();
  return s;
}

void Renderer::shutdown() {
  if (!impl_) return;
  Impl& m = *impl_;
  m.driven_views.release();
  for (VkPipeline& p : m.passes)
    if (p != VK_NULL_HANDLE) vkDestroyPipeline(m.device(), p, m.allocator());
  destroyComputeLayout(m.device(), m.allocator(), &m.compute_layout);
  destroyPyramidPasses(m.device(), m.allocator(), &m.pyramid_passes);
  destroyImpostorPasses(m.device(), m.allocator(), &m.impostor_passes);
  for (SkinnedLayout* l : {&m.layout, &m.driven_layout}) {
    if (l->pipeline_layout != VK_NULL_HANDLE)
      vkDestroyPipelineLayout(m.device(), l->pipeline_layout, m.allocator());
    if (l->set_layout != VK_NULL_HANDLE)
      vkDestroyDescriptorSetLayout(m.device(), l->set_layout, m.allocator());
  }
  m.objects.destroy(&m.unbuilt);
  m.objects.destroy(&m.no_pyramid);
  for (auto& c : m.characters) destroyCharacter(&m.objects, c.get());
  for (GpuBuffer& b : m.finished_staging) m.objects.destroy(&b);
  m.objects.destroy(&m.ring);
  m.objects.destroy(&m.custom);
  m.objects.destroy(&m.no_morphs);
  m.objects.destroy(&m.placeholder_staging);
  for (VkSampler sampler : {m.nearest, m.linear})
    if (sampler != VK_NULL_HANDLE) vkDestroySampler(m.device(), sampler, m.allocator());
  for (ProgramModules& p : m.programs) destroyProgramModules(m.device(), m.allocator(), &p);
  m.objects.release();  // The memory blocks, every buffer and image gone.
  impl_.reset();
}

BatchLimits Renderer::batchLimits() const {
  BatchLimits l;
  l.max_uniform_block_size_bytes = uint32_t(kRecordsRange);
  l.uniform_buffer_offset_alignment = impl_ ? uint32_t(impl_->ubo_alignment) : 256;
  l.max_instances_per_draw = kVulkanMaxInstances;
  return l;
}

Status Renderer::addCharacter(const Character& character, const BakedPalette& palette,
                              CharacterId* out) {
  if (!impl_) return {StatusCode::kInvalidArgument, "vk::Renderer::addCharacter: not initialized"};
  if (out == nullptr) return {StatusCode::kInvalidArgument, "vk::Renderer::addCharacter: null id"};
  Impl& m = *impl_;
  auto c = std::make_unique<Impl::Character>();
  VertexStream stream;
  StagingLimits limits;
  limits.max_image_size = m.max_image_size;
  limits.morph_lod_share = m.desc.morph_lod_share;
  Status s = stageCharacter(&m.objects, character, palette, limits, c.get(), &stream);
  // Each kind's program for the mesh (8 influences, vertex words) and its pipeline: shaded,
  // depth only, and with motion vectors when the renderer draws them.
  const SkinnedMesh& mesh = character.mesh;
  MeshVariant variant;
  variant.morph_targets = !mesh.morph_targets.empty();
  variant.eight_influences = !mesh.joints1.empty();
  variant.vertex_words = !mesh.texcoords1.empty() || !mesh.colors.empty();
  const VkFormat depth_only_format = m.desc.depth_only_format != VK_FORMAT_UNDEFINED
                                         ? m.desc.depth_only_format
                                         : m.desc.depth_format;
  const RenderingFormats formats[kVulkanKinds] = {
      {m.desc.color_format, m.desc.depth_format, VK_FORMAT_UNDEFINED, m.desc.samples},
      {VK_FORMAT_UNDEFINED, depth_only_format, VK_FORMAT_UNDEFINED, m.desc.depth_only_samples},
      {m.desc.color_format, m.desc.depth_format, m.desc.motion_format, m.desc.samples}};
  for (int layers = 0; layers < 2; ++layers)
    for (size_t k = 0; k < kVulkanKinds && s.isOk(); ++k) {
      const VulkanKind kind = VulkanKind(k);
      uint32_t& program = c->programs[layers][k];
      program = uint32_t(vulkanProgramIndex(kind, layers == 1, variant));
      if (kind == VulkanKind::kMotion && m.desc.motion_format == VK_FORMAT_UNDEFINED) continue;
      s = createSkinnedPipeline(m.device(), m.allocator(), m.programs[program],
                                m.layout.pipeline_layout, formats[k], stream,
                                &c->pipelines[layers][k]);
    }
  // The GPU-driven draws, shaded and depth only, skinned in the vertex stage (without and with
  // layers) and pre-skinned; the pre-skinning passes of the mesh's variant.
  for (size_t k = 0; k < kVulkanKinds && s.isOk() && m.desc.gpu_driven; ++k) {
    if (VulkanKind(k) == VulkanKind::kMotion && m.desc.motion_format == VK_FORMAT_UNDEFINED)
      continue;
    for (int layering = kNoLayers; layering <= kComposedLayers && s.isOk(); ++layering) {
      uint32_t& program = c->driven_programs[layering][k];
      program = uint32_t(vulkanProgramIndex(VulkanKind(k), layering != kNoLayers, variant, true,
                                            layering == kComposedLayers));
      s = createSkinnedPipeline(m.device(), m.allocator(), m.programs[program],
                                m.driven_layout.pipeline_layout, formats[k], stream,
                                &c->driven_pipelines[layering][k]);
    }
    c->pulled_programs[k] =
        uint32_t(vulkanPulledProgramIndex(VulkanKind(k), stream.tangent_offset != 0, variant));
    if (s.isOk())
      s = createSkinnedPipeline(m.device(), m.allocator(), m.programs[c->pulled_programs[k]],
                                m.driven_layout.pipeline_layout, formats[k], stream,
                                &c->pulled_pipelines[k]);
  }
  // The pre-skinning passes by layering, and the layer compose passes, each alone and with the
  // previous positions (records) when the renderer draws motion vectors.
  using si::detail::ProgramId;
  const ProgramId skin_ids[3][2] = {
      {ProgramId::kGpuSkin, ProgramId::kGpuSkinMotion},
      {ProgramId::kGpuSkinLayers, ProgramId::kGpuSkinMotionLayers},
      {ProgramId::kGpuSkinComposed, ProgramId::kGpuSkinMotionComposed}};
  for (int motion = 0; motion < 2 && s.isOk() && m.desc.gpu_driven; ++motion) {
    if (motion == 1 && m.desc.motion_format == VK_FORMAT_UNDEFINED) continue;
    for (int layering = kNoLayers; layering <= kComposedLayers && s.isOk(); ++layering) {
      uint32_t& program = c->skin_programs[layering][motion];
      program = uint32_t(vulkanComputeProgramIndex(skin_ids[layering][motion], variant));
      s = createComputePipeline(m.device(), m.allocator(), m.programs[program],
                                m.compute_layout.pipeline_layout,
                                &c->skin_pipelines[layering][motion]);
    }
    c->compose_programs[motion] = uint32_t(vulkanComputeProgramIndex(
        motion == 1 ? ProgramId::kGpuLayerComposeMotion : ProgramId::kGpuLayerCompose, variant));
    if (s.isOk())
      s = createComputePipeline(m.device(), m.allocator(), m.programs[c->compose_programs[motion]],
                                m.compute_layout.pipeline_layout, &c->compose_pipelines[motion]);
  }
  if (s.isOk())
    s = createCharacterSet(m.device(), m.allocator(), m.layout,
                           {m.ring, m.nearest, m.linear, m.custom, m.no_morphs}, *c, nullptr,
                           &c->pool, &c->set);
  c->stream = stream;
  c->variant = variant;
  c->palette_source = &palette;
  if (!s.isOk()) {
    destroyCharacter(&m.objects, c.get());
    return s;
  }
  out->index = uint32_t(m.characters.size());
  m.characters.push_back(std::move(c));
  return Status::ok();
}

Status Renderer::recordUploads(VkCommandBuffer cmd) {
  if (!impl_) return {StatusCode::kInvalidArgument, "vk::Renderer::recordUploads: not initialized"};
  Impl& m = *impl_;
  if (!m.placeholders_uploaded) {
    recordImageUpload(cmd, m.placeholder_staging.buffer, {&m.custom, 0, false});
    recordImageUpload(cmd, m.placeholder_staging.buffer, {&m.no_morphs, 16, false});
    if (m.no_pyramid.image != VK_NULL_HANDLE)
      recordImageUpload(cmd, m.placeholder_staging.buffer, {&m.no_pyramid, 32, false});
    m.finished_staging.push_back(m.placeholder_staging);
    m.placeholder_staging = GpuBuffer{};
    m.placeholders_uploaded = true;
  }
  for (auto& c : m.characters) {
    if (c->uploads_recorded) continue;
    for (const BufferUpload& u : c->buffer_uploads) {
      const VkBufferCopy copy{u.offset, 0, u.buffer->size};
      vkCmdCopyBuffer(cmd, c->staging.buffer, u.buffer->buffer, 1, &copy);
    }
    for (const ImageUpload& u : c->image_uploads) recordImageUpload(cmd, c->staging.buffer, u);
    m.finished_staging.push_back(c->staging);
    c->staging = GpuBuffer{};
    c->uploads_recorded = true;
  }
  // Impostor captures (buildImpostor), after their characters' uploads.
  for (auto& c : m.characters)
    if (c->capture.pending() && !c->impostor.captured)
      recordImpostorCapture(cmd, c->capture, m.layout.pipeline_layout, c->vertices.buffer,
                            c->indices.buffer, m.impostor_passes, &c->impostor);
  recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                          VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                      VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT |
                          VK_ACCESS_UNIFORM_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
  return Status::ok();
}

void Renderer::uploadsComplete() {
  if (!impl_) return;
  for (GpuBuffer& b : impl_->finished_staging) impl_->objects.destroy(&b);
  impl_->finished_staging.clear();
  for (auto& c : impl_->characters)
    if (c->impostor.captured) releaseImpostorCapture(&impl_->objects, &c->capture);
}

Status Renderer::beginFrame(uint32_t frame) {
  if (!impl_) return {StatusCode::kInvalidArgument, "vk::Renderer::beginFrame: not initialized"};
  if (frame >= impl_->desc.frames_in_flight)
    return {StatusCode::kInvalidArgument,
            strCat("vk::Renderer::beginFrame: slot ", frame, " past frames_in_flight ",
                   impl_->desc.frames_in_flight)};
  impl_->frame = int32_t(frame);
  impl_->frame_used = 0;
  impl_->driven_views.beginFrame(frame);
  return Status::ok();
}

Status Renderer::discardFrame() {
  if (!impl_ || impl_->frame < 0)
    return {StatusCode::kInvalidArgument, "vk::Renderer::discardFrame: no frame was begun"};
  impl_->driven_views.discardFrame(uint32_t(impl_->frame));
  impl_->frame = -1;
  impl_->frame_used = 0;
  return Status::ok();
}

}  // namespace si::vk
