// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// vk::Renderer::buildImpostor: the atlas planned as si::gl plans it (crowd/impostor_plan.h), made
// on the host's device, and its capture staged for recordUploads() (impostor_atlas.h): the
// capture crowd's batches' records and default blocks written, the capture program's pipeline
// made for the character's mesh, supersampled the capture's own layers and the resolve pass's
// set.
#include <algorithm>
#include <cstring>
#include <iterator>

#include "core/str_cat.h"
#include "crowd/impostor_plan.h"
#include "crowd/ring_frame.h"
#include "vk/character_set.h"
#include "vk/draw_state.h"
#include "vk/renderer_impl.h"

namespace si::vk {

using si::detail::strCat;
using namespace si::vk::detail;

namespace {

// The resolve pass's set for `capture` (supersampled): its capture layers read, the atlas's level
// 0 (a view of its own) written, its uniforms in the capture's staging.
Status createResolveSet(VkDevice device, const VkAllocationCallbacks* allocator,
                        const ImpostorPasses& passes, const ImpostorAtlas& atlas,
                        ImpostorCapture* capture) {
  auto v = vkStruct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
  v.image = atlas.image.image;
  v.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
  v.format = VK_FORMAT_R8G8B8A8_UNORM;
  v.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, ImpostorAtlas::kLayers};
  Status s = checkVk(vkCreateImageView(device, &v, allocator, &capture->atlas_level0),
                     "vkCreateImageView (the impostor atlas's level 0)");
  if (s.isOk())
    s = createDescriptorSet(device, allocator, passes.resolve_layout.set_layout,
                            passes.resolve_layout.bindings, &capture->resolve_pool,
                            &capture->resolve_set);
  if (!s.isOk()) return s;
  const VkDescriptorImageInfo read{passes.sampler, capture->supersampled.view,
                                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  const VkDescriptorImageInfo written{VK_NULL_HANDLE, capture->atlas_level0,
                                      VK_IMAGE_LAYOUT_GENERAL};
  const VkDescriptorBufferInfo defaults{capture->staging.buffer, 0, kComputeDefaultsRange};
  std::vector<VkWriteDescriptorSet> writes;
  for (const VkDescriptorSetLayoutBinding& binding : passes.resolve_layout.bindings) {
    auto w = vkStruct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    w.dstSet = capture->resolve_set;
    w.dstBinding = binding.binding;
    w.descriptorCount = 1;
    w.descriptorType = binding.descriptorType;
    if (binding.binding == kResolveCaptureBinding)
      w.pImageInfo = &read;
    else if (binding.binding == kResolveAtlasBinding)
      w.pImageInfo = &written;
    else
      w.pBufferInfo = &defaults;
    writes.push_back(w);
  }
  vkUpdateDescriptorSets(device, uint32_t(writes.size()), writes.data(), 0, nullptr);
  return Status::ok();
}

}  // namespace

bool Renderer::hasImpostor(CharacterId id) const {
  return impl_ && id.index < impl_->characters.size() &&
         impl_->characters[id.index]->impostor.made();
}

Status Renderer::buildImpostor(CharacterId id, const ImpostorDesc& desc, ImpostorInfo* info) {
  constexpr const char* kCall = "vk::Renderer::buildImpostor";
  if (!impl_) return {StatusCode::kInvalidArgument, strCat(kCall, ": not initialized")};
  Impl& m = *impl_;
  if (id.index >= m.characters.size())
    return {StatusCode::kInvalidArgument, strCat(kCall, ": no character ", id.index)};
  Impl::Character& c = *m.characters[id.index];
  if (!m.desc.gpu_driven)
    return {StatusCode::kUnsupported,
            strCat(kCall,
                   ": impostors are drawn on the GPU-driven path only (RendererDesc::"
                   "gpu_driven)")};
  const BakedPalette& palette = *c.palette_source;
  const uint32_t sub_meshes = uint32_t(c.sub_meshes.size());
  // The atlas is an image and a colour attachment, the capture's depth an attachment, drawn
  // through one viewport.
  const si::detail::ImpostorSide sides[] = {{m.max_image_size, "maxImageDimension2D"},
                                            {m.max_framebuffer_size, "maxFramebufferWidth/Height"},
                                            {m.max_viewport_size, "maxViewportDimensions"}};
  si::detail::ImpostorPlan plan;
  const Status planned = si::detail::planImpostor(
      palette, sub_meshes, desc, Span<const si::detail::ImpostorSide>(sides, std::size(sides)), 4,
      kCall, &plan);
  if (info != nullptr) *info = plan.info;  // Reported before anything is allocated.
  if (!planned.isOk()) return planned;
  VkFormatProperties depth_format{};
  vkGetPhysicalDeviceFormatProperties(m.desc.physical_device, ImpostorAtlas::kCaptureDepthFormat,
                                      &depth_format);
  if ((depth_format.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) == 0)
    return {StatusCode::kUnsupported,
            strCat(kCall, ": the device renders no VK_FORMAT_D32_SFLOAT depth (the capture's)")};

  // The capture crowd's batches, written into the capture's staging: their records, the
  // fragment stage's defaults, each batch's vertex defaults, then the clip table.
  CrowdManager crowd;
  Camera camera;
  Status s = si::detail::makeCaptureCrowd(plan, palette, sub_meshes, &crowd, &camera);
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(batchLimits());
  if (!s.isOk()) return s;
  const si::detail::RingFrame frame = si::detail::planRingFrame(
      batcher, crowd.view(), uint32_t(m.ubo_alignment), si::detail::RingContents(), true);
  const VkDeviceSize defaults_at = alignUp(frame.end, kDefaultsRange);
  // Every batch of the capture crowd at LOD 0 is drawn (a sub-mesh without indices aside).
  ImpostorCapture capture;
  std::vector<DrawBatch> draws;
  std::vector<uint8_t> records(frame.end);
  s = si::detail::writeRingFrame(batcher, crowd.view(), frame, records.data(), records.size(), {},
                                 &draws);
  if (!s.isOk()) return s;
  const VkDeviceSize table_at = alignUp(defaults_at + kDefaultsRange * (1 + draws.size()), 16);
  // The clip table: the clips, then every cell's covered rectangle at every level, measured on
  // the GPU after the capture (impostor_coverage.comp.glsl; si::gl reads the atlas back, and a
  // guest waits for no submission) over these.
  const size_t entries = size_t(plan.cells) * plan.levels;
  const std::vector<uint32_t> table =
      si::detail::impostorClipTable(plan, std::vector<uint32_t>(entries, 0u));
  // The coverage passes' uniforms: each level's, then the packing pass's; then the resolve
  // pass's two (supersampled).
  const VkDeviceSize coverage_at = alignUp(table_at + table.size() * 4, kComputeDefaultsRange);
  const VkDeviceSize resolve_at = coverage_at + kComputeDefaultsRange * (plan.levels + 1);
  // The dynamic bindings' ranges read past their offsets: a block's worth past the end.
  const VkDeviceSize staging_bytes = resolve_at + kComputeDefaultsRange * 2 + kRecordsRange;
  // Supersampled, the capture draws into layers of its own, averaged into the atlas after.
  const uint32_t ss = plan.info.capture_supersample;
  const uint32_t cw = plan.info.width * ss, ch = plan.info.height * ss;

  const auto fail = [&](Status why) {
    releaseImpostorCapture(&m.objects, &capture);
    return why;
  };
  ImpostorAtlas atlas;
  capture.factor = ss;
  s = m.objects.createImage(
      plan.info.width, plan.info.height, ImpostorAtlas::kLayers, plan.levels,
      VK_FORMAT_R8G8B8A8_UNORM, true, "the impostor atlas", &atlas.image,
      ss > 1 ? VK_IMAGE_USAGE_STORAGE_BIT : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
  if (s.isOk()) s = createAtlasSampler(m.device(), m.allocator(), desc.lod_bias, &atlas.sampler);
  if (s.isOk() && ss > 1)
    s = m.objects.createImage(cw, ch, ImpostorAtlas::kLayers, 1, VK_FORMAT_R8G8B8A8_UNORM, true,
                              "the impostor's supersampled capture", &capture.supersampled,
                              VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
  if (s.isOk())
    s = m.objects.createBuffer(
        table.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
        false, "the impostor clip table", &atlas.clips);
  if (s.isOk())
    s = m.objects.createImage(cw, ch, 1, 1, ImpostorAtlas::kCaptureDepthFormat, false,
                              "the impostor capture's depth", &capture.depth,
                              VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT);
  for (uint32_t k = 0; k < ImpostorAtlas::kLayers && s.isOk(); ++k) {
    auto v = vkStruct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
    v.image = ss > 1 ? capture.supersampled.image : atlas.image.image;
    v.viewType = VK_IMAGE_VIEW_TYPE_2D;
    v.format = VK_FORMAT_R8G8B8A8_UNORM;
    v.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, k, 1};
    s = checkVk(vkCreateImageView(m.device(), &v, m.allocator(), &capture.layers[k]),
                "vkCreateImageView (the impostor atlas's layer)");
  }
  if (s.isOk())
    s = m.objects.createBuffer(staging_bytes,
                               VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               true, "the impostor capture's records", &capture.staging);
  if (s.isOk()) {
    RenderingFormats formats;
    formats.color = VK_FORMAT_R8G8B8A8_UNORM;
    formats.color_count = ImpostorAtlas::kLayers;
    formats.depth = ImpostorAtlas::kCaptureDepthFormat;
    s = createSkinnedPipeline(m.device(), m.allocator(),
                              m.programs[vulkanCaptureProgramIndex(c.variant)],
                              m.layout.pipeline_layout, formats, c.stream, &capture.pipeline);
  }
  // The extents the coverage passes gather: minima and maxima, 4 words each per cell and level.
  if (s.isOk())
    s = m.objects.createBuffer(
        VkDeviceSize(entries) * 32,
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false,
        "the impostor coverage's extents", &capture.extents);
  const ImpostorPasses& passes = m.impostor_passes;
  if (s.isOk() && ss > 1) s = createResolveSet(m.device(), m.allocator(), passes, atlas, &capture);
  if (s.isOk())
    s = createDescriptorSet(m.device(), m.allocator(), passes.coverage_layout.set_layout,
                            passes.coverage_layout.bindings, &capture.coverage_pool,
                            &capture.coverage_set);
  if (s.isOk()) {
    std::vector<VkWriteDescriptorSet> writes;
    std::vector<VkDescriptorBufferInfo> buffers(passes.coverage_layout.bindings.size());
    const VkDescriptorImageInfo image{passes.sampler, atlas.image.view,
                                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    for (size_t k = 0; k < passes.coverage_layout.bindings.size(); ++k) {
      const VkDescriptorSetLayoutBinding& binding = passes.coverage_layout.bindings[k];
      auto w = vkStruct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
      w.dstSet = capture.coverage_set;
      w.dstBinding = binding.binding;
      w.descriptorCount = 1;
      w.descriptorType = binding.descriptorType;
      if (binding.binding == kImpostorAtlasBinding) {
        w.pImageInfo = &image;
      } else {
        buffers[k] = binding.binding == kImpostorClipsBinding
                         ? VkDescriptorBufferInfo{atlas.clips.buffer, 0, VK_WHOLE_SIZE}
                     : binding.binding == kImpostorQuadsBinding
                         ? VkDescriptorBufferInfo{capture.extents.buffer, 0, VK_WHOLE_SIZE}
                         : VkDescriptorBufferInfo{capture.staging.buffer, 0, kComputeDefaultsRange};
        w.pBufferInfo = &buffers[k];
      }
      writes.push_back(w);
    }
    vkUpdateDescriptorSets(m.device(), uint32_t(writes.size()), writes.data(), 0, nullptr);
  }
  if (s.isOk())
    s = createCharacterSet(m.device(), m.allocator(), m.layout,
                           {capture.staging, m.nearest, m.linear, m.custom, m.no_morphs}, c,
                           nullptr, &capture.pool, &capture.set);
  if (!s.isOk()) {
    releaseImpostorAtlas(&m.objects, &atlas);
    return fail(s);
  }

  auto* staging = static_cast<uint8_t*>(capture.staging.mapped);
  std::memcpy(staging, records.data(), records.size());
  std::memcpy(staging + table_at, table.data(), table.size() * 4);
  const ProgramModules& program = m.programs[vulkanCaptureProgramIndex(c.variant)];
  writeFragmentDefaults(staging + defaults_at, program.fragment_reflection, m.desc.light_direction);
  const glm::mat4 vp = vulkanViewProjection(camera);
  for (size_t k = 0; k < draws.size(); ++k) {
    const DrawBatch& d = draws[k];
    if (d.sub_mesh >= c.sub_meshes.size()) continue;
    const IndexRange range = c.lodRange(d.sub_mesh, d.lod);
    if (range.index_count == 0) continue;
    const VkDeviceSize vertex_at = defaults_at + kDefaultsRange * (1 + k);
    writeDefault(staging + vertex_at, program.vertex_reflection, "u_view_projection", &vp[0][0],
                 64);
    const uint32_t lod = d.lod;
    writeDefault(staging + vertex_at, program.vertex_reflection, "u_lod", &lod, 4);
    ImpostorCapture::Draw draw;
    draw.first_index = range.first_index;
    draw.index_count = range.index_count;
    draw.instances = d.instance_count;
    // Dynamic offsets in binding order: the records, the vertex and the fragment defaults (the
    // layer blocks and mask table, unread, at 0).
    for (uint32_t b : m.layout.dynamic_bindings)
      draw.offsets.push_back(uint32_t(b == kRecordsBinding            ? d.byte_offset
                                      : b == kVertexDefaultsBinding   ? vertex_at
                                      : b == kFragmentDefaultsBinding ? defaults_at
                                                                      : 0));
    capture.draws.push_back(std::move(draw));
  }
  capture.table_at = table_at;
  // The coverage passes: per level one thread a texel, then one a cell and level (rows of at
  // most 65,535 groups of 64).
  const glm::uvec4 grid(plan.columns, plan.rows, plan.cell, uint32_t(plan.clips.size()));
  for (uint32_t k = 0; k <= plan.levels; ++k) {
    const bool rects = k == plan.levels;
    const uint32_t w = std::max(plan.info.width >> k, 1u), h = std::max(plan.info.height >> k, 1u);
    const uint64_t threads = rects ? uint64_t(entries) : uint64_t(w) * h;
    const uint64_t groups = std::max<uint64_t>((threads + 63) / 64, 1);
    ImpostorCapture::CoveragePass pass;
    pass.defaults_at = uint32_t(coverage_at + kComputeDefaultsRange * k);
    pass.groups_x = uint32_t(std::min<uint64_t>(groups, 65535));
    pass.groups_y = uint32_t((groups + pass.groups_x - 1) / pass.groups_x);
    const SpirvReflection& r = passes.coverage_programs[rects ? 1 : 0]->compute_reflection;
    const glm::uvec4 level(k, w, h, plan.levels);
    writeDefault(staging + pass.defaults_at, r, "u_coverage_level", &level[0], 16);
    writeDefault(staging + pass.defaults_at, r, "u_coverage_atlas", &grid[0], 16);
    capture.coverage.push_back(pass);
  }
  if (ss > 1) {  // Every layer's means, then the surface layer's one material.
    const SpirvReflection& r = passes.resolve_program->compute_reflection;
    for (int k = 0; k < 2; ++k) {
      capture.resolve_at[k] = uint32_t(resolve_at + kComputeDefaultsRange * k);
      const glm::ivec3 size(int(plan.info.width), int(plan.info.height),
                            k == 0 ? 0 : int(ImpostorAtlas::kSurfaceLayer));
      const int factor = int(ss), codes = k;
      writeDefault(staging + capture.resolve_at[k], r, "u_size", &size[0], 12);
      writeDefault(staging + capture.resolve_at[k], r, "u_factor", &factor, 4);
      writeDefault(staging + capture.resolve_at[k], r, "u_codes", &codes, 4);
    }
  }

  // The atlas's numbers, as si::gl's ImpostorAtlas holds them.
  static_cast<si::detail::ImpostorGrid&>(atlas) = si::detail::impostorGrid(plan, palette);
  // A rebuild: the host has waited for the device's work on the old atlas (renderer.h).
  releaseImpostorAtlas(&m.objects, &c.impostor);
  releaseImpostorCapture(&m.objects, &c.capture);
  c.impostor = atlas;
  c.capture = std::move(capture);
  return Status::ok();
}

}  // namespace si::vk
