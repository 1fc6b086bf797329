// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// vk::Renderer's GPU-driven path: its layouts, pipelines and placeholders made at init, and its
// entry points (the passes, the draws, what they counted, their memory), over
// gpu_driven_views.h.
#include <vector>

#include "core/str_cat.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/vk/renderer.h"
#include "vk/draw_state.h"
#include "vk/renderer_impl.h"
#include "vk/vulkan_programs.h"

namespace si::vk {

using si::detail::strCat;
using namespace si::vk::detail;

Status Renderer::Impl::initGpuDriven(const VkPhysicalDeviceLimits& limits) {
  std::vector<StageReflection> stages;
  const ProgramModules* pass_modules[3] = {};
  const si::detail::ProgramId pass_ids[3] = {si::detail::ProgramId::kCull,
                                             si::detail::ProgramId::kCullCommands,
                                             si::detail::ProgramId::kCullScatter};
  for (int k = 0; k < 3; ++k) pass_modules[k] = &programs[vulkanComputeProgramIndex(pass_ids[k])];
  // The layout's passes: the three, the pre-skinning passes of every mesh variant and the layer
  // compose passes (every GPU-driven pass but the depth pyramid's and the impostors').
  std::vector<const ProgramModules*> layout_passes(pass_modules, pass_modules + 3);
  for (size_t k = 0; k < programs.size(); ++k) {
    using si::detail::ProgramId;
    const ProgramId id = vulkanPrograms()[k].id;
    if (vulkanPrograms()[k].compute &&
        (id == ProgramId::kGpuSkin || id == ProgramId::kGpuSkinMotion ||
         id == ProgramId::kGpuSkinLayers || id == ProgramId::kGpuSkinMotionLayers ||
         id == ProgramId::kGpuSkinComposed || id == ProgramId::kGpuSkinMotionComposed ||
         id == ProgramId::kGpuLayerCompose || id == ProgramId::kGpuLayerComposeMotion))
      layout_passes.push_back(&programs[k]);
  }
  for (size_t k = 0; k < programs.size(); ++k) {
    const VulkanProgram& p = vulkanPrograms()[k];
    if (!p.gpu_driven || p.compute || p.impostor) continue;  // Impostors: a layout of their own.
    stages.push_back({VK_SHADER_STAGE_VERTEX_BIT, &programs[k].vertex_reflection});
    stages.push_back({VK_SHADER_STAGE_FRAGMENT_BIT, &programs[k].fragment_reflection});
  }
  Status s = createSkinnedLayout(device(), allocator(),
                                 Span<const StageReflection>(stages.data(), stages.size()),
                                 &driven_layout);
  if (s.isOk())
    s = createComputeLayout(
        device(), allocator(),
        Span<const ProgramModules* const>(layout_passes.data(), layout_passes.size()),
        drivenPassBindingType, "the GPU-driven passes", &compute_layout);
  for (int k = 0; k < 3 && s.isOk(); ++k)
    s = createComputePipeline(device(), allocator(), *pass_modules[k],
                              compute_layout.pipeline_layout, &passes[k]);
  if (s.isOk()) {
    using si::detail::ProgramId;
    s = createPyramidPasses(
        device(), allocator(), programs[vulkanComputeProgramIndex(ProgramId::kHizCopy)],
        programs[vulkanComputeProgramIndex(ProgramId::kHizCopyMultisample)],
        programs[vulkanComputeProgramIndex(ProgramId::kHizReduce)], nearest, &pyramid_passes);
  }
  if (s.isOk()) {
    // The impostor draws render where the character's draws do (renderer.cpp's addCharacter).
    const VkFormat depth_only_format =
        desc.depth_only_format != VK_FORMAT_UNDEFINED ? desc.depth_only_format : desc.depth_format;
    s = createImpostorPasses(
        device(), allocator(), programs,
        {desc.color_format, desc.depth_format, desc.motion_format, desc.samples},
        {VK_FORMAT_UNDEFINED, depth_only_format, VK_FORMAT_UNDEFINED, desc.depth_only_samples},
        &impostor_passes);
  }
  for (const SkinnedLayout* l : {&driven_layout, &impostor_passes.draw_layout})
    if (s.isOk() && l->dynamic_bindings.size() > kMaxDrawOffsets)
      s = {StatusCode::kUnsupported,
           strCat("vk::Renderer::init: the GPU-driven draw programs declare ",
                  l->dynamic_bindings.size(), " dynamic buffers, more than the ", kMaxDrawOffsets,
                  " the draws offset")};
  if (s.isOk())
    s = objects.createBuffer(256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                             "the GPU-driven passes' unbuilt bindings", &unbuilt);
  if (s.isOk())
    s = objects.createImage(1, 1, 1, 1, VK_FORMAT_R32_SFLOAT, false,
                            "the depth pyramid's placeholder", &no_pyramid);
  if (!s.isOk()) return s;
  DrivenShared shared;
  shared.objects = &objects;
  shared.compute_layout = &compute_layout;
  for (int k = 0; k < 3; ++k) {
    shared.passes[k] = passes[k];
    shared.pass_modules[k] = pass_modules[k];
  }
  shared.draw_layout = &driven_layout;
  shared.ring = &ring;
  shared.nearest = nearest;
  shared.linear = linear;
  shared.custom = &custom;
  shared.no_morphs = &no_morphs;
  shared.unbuilt = &unbuilt;
  shared.no_pyramid = &no_pyramid;
  shared.pyramid_passes = &pyramid_passes;
  shared.impostors = &impostor_passes;
  shared.single_sampled =
      desc.samples == VK_SAMPLE_COUNT_1_BIT && desc.depth_only_samples == VK_SAMPLE_COUNT_1_BIT;
  shared.max_image_size = max_image_size;
  shared.max_groups_x = limits.maxComputeWorkGroupCount[0];
  shared.max_groups_y = limits.maxComputeWorkGroupCount[1];
  shared.max_storage_range = limits.maxStorageBufferRange;
  shared.frames_in_flight = desc.frames_in_flight;
  shared.ring_bytes = desc.gpu_driven_ring_bytes;
  shared.idle_frames = desc.gpu_driven_idle_frames;
  shared.motion = desc.motion_format != VK_FORMAT_UNDEFINED;
  shared.programs = &programs;
  driven_views.init(shared);
  return Status::ok();
}

Status Renderer::recordGpuDrivenPasses(VkCommandBuffer cmd, CharacterId id, const CrowdView& view,
                                       const Camera& camera, PassStats* stats, GpuCulling culling) {
  if (!impl_)
    return {StatusCode::kInvalidArgument, "vk::Renderer::recordGpuDrivenPasses: not initialized"};
  Impl& m = *impl_;
  if (!m.desc.gpu_driven)
    return {StatusCode::kUnsupported,
            "vk::Renderer::recordGpuDrivenPasses: the renderer was not made for the GPU-driven "
            "path (RendererDesc::gpu_driven)"};
  const Status checked = m.checkFrame("vk::Renderer::recordGpuDrivenPasses", id);
  if (!checked.isOk()) return checked;
  const Impl::Character& c = *m.characters[id.index];
  if (view.crowd() == nullptr)
    return {StatusCode::kInvalidArgument,
            "vk::Renderer::recordGpuDrivenPasses: the view is not attached to a crowd"};
  const CrowdManager& crowd = *view.crowd();
  const CrowdExport exported(crowd);
  const char* unbuilt = exported.livePoseCount() > 0 ? "live poses" : nullptr;
  if (unbuilt != nullptr)
    return {StatusCode::kUnsupported,
            strCat("vk::Renderer::recordGpuDrivenPasses: the Vulkan back-end's GPU-driven path "
                   "does not draw a crowd with ",
                   unbuilt, " yet")};
  if (crowd.desc().impostor_lod != 0) {
    // As si::Renderer: impostors draw no motion vectors.
    if (m.desc.motion_format != VK_FORMAT_UNDEFINED)
      return {StatusCode::kUnsupported,
              "vk::Renderer::recordGpuDrivenPasses: impostors draw no motion vectors (a crowd "
              "with CrowdDesc::impostor_lod, a renderer with RendererDesc::motion_format)"};
    if (!c.impostor.made() || !c.impostor.captured)
      return {StatusCode::kInvalidArgument,
              "vk::Renderer::recordGpuDrivenPasses: the crowd has an impostor level "
              "(CrowdDesc::impostor_lod) and the character no impostor atlas captured "
              "(buildImpostor, then recordUploads)"};
  }
  if (culling != GpuCulling::kFrustum && culling != GpuCulling::kOcclusion)
    return {StatusCode::kInvalidArgument,
            strCat("vk::Renderer::recordGpuDrivenPasses: no GpuCulling ", int(culling))};
  const Status s = m.driven_views.recordPasses(cmd, uint32_t(m.frame), m.region(), id.index, c,
                                               view, camera, culling == GpuCulling::kOcclusion);
  if (s.isOk() && stats != nullptr) {
    const CrowdUpload& u = m.driven_views.lastUpload();
    stats->state_bytes_uploaded = u.state_bytes;
    stats->upload_regions = u.regions;
    stats->whole_upload = u.whole;
  }
  return s;
}

Status Renderer::recordGpuDrivenOcclusion(VkCommandBuffer cmd, CharacterId id,
                                          const CrowdView& view, const DepthSource& depth) {
  static constexpr const char* kCall = "vk::Renderer::recordGpuDrivenOcclusion";
  if (!impl_) return {StatusCode::kInvalidArgument, strCat(kCall, ": not initialized")};
  Impl& m = *impl_;
  if (!m.desc.gpu_driven)
    return {StatusCode::kUnsupported, strCat(kCall,
                                             ": the renderer was not made for the GPU-driven path "
                                             "(RendererDesc::gpu_driven)")};
  const Status checked = m.checkFrame(kCall, id);
  if (!checked.isOk()) return checked;
  const VkImageLayout l = depth.layout;
  const bool readable =
      l == VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL ||
      l == VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL || l == VK_IMAGE_LAYOUT_READ_ONLY_OPTIMAL ||
      l == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL || l == VK_IMAGE_LAYOUT_GENERAL;
  const uint32_t samples = uint32_t(depth.samples);
  const bool sample_bit = samples != 0 && samples <= 64 && (samples & (samples - 1)) == 0;
  if (depth.view == VK_NULL_HANDLE || !readable || depth.extent.width == 0 ||
      depth.extent.height == 0 || !sample_bit || depth.offset.x < 0 || depth.offset.y < 0)
    return {StatusCode::kInvalidArgument,
            strCat(kCall, ": the depth needs a view, a layout compute shaders read (VkImageLayout ",
                   int(l), "), an extent (", depth.extent.width, " x ", depth.extent.height,
                   ") at a non-negative offset (", depth.offset.x, ", ", depth.offset.y,
                   ") and samples (", samples, ")")};
  return m.driven_views.recordOcclusion(cmd, uint32_t(m.frame), m.region(), id.index,
                                        *m.characters[id.index], view, depth);
}

Status Renderer::readGpuDrivenCounts(CharacterId id, const CrowdView& view,
                                     GpuDrivenCounts* out) const {
  if (!impl_ || out == nullptr)
    return {StatusCode::kInvalidArgument,
            "vk::Renderer::readGpuDrivenCounts: not initialized, or a null output"};
  if (id.index >= impl_->characters.size())
    return {StatusCode::kInvalidArgument,
            strCat("vk::Renderer::readGpuDrivenCounts: no character ", id.index)};
  return impl_->driven_views.readCounts(id.index, *impl_->characters[id.index], view, out);
}

GpuDrivenMemory Renderer::gpuDrivenMemory() const {
  return impl_ ? impl_->driven_views.memory() : GpuDrivenMemory();
}

Status Renderer::recordGpuDrivenDraw(VkCommandBuffer cmd, const DrawTarget& target, CharacterId id,
                                     const CrowdView& view, DrawStats* stats) {
  if (!impl_)
    return {StatusCode::kInvalidArgument, "vk::Renderer::recordGpuDrivenDraw: not initialized"};
  Impl& m = *impl_;
  if (!m.desc.gpu_driven)
    return {StatusCode::kUnsupported,
            "vk::Renderer::recordGpuDrivenDraw: the renderer was not made for the GPU-driven "
            "path (RendererDesc::gpu_driven)"};
  Status checked = Impl::checkTarget("vk::Renderer::recordGpuDrivenDraw", target);
  if (checked.isOk()) checked = m.checkFrame("vk::Renderer::recordGpuDrivenDraw", id);
  if (!checked.isOk()) return checked;
  const Impl::Character& c = *m.characters[id.index];
  return m.driven_views.recordDraw(cmd, m.region(), id.index, c, view, target,
                                   m.desc.light_direction, stats);
}

}  // namespace si::vk
