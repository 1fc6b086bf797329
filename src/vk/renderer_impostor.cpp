// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// vk::Renderer::buildImpostor: the atlas planned as si::gl plans it (crowd/impostor_plan.h), made
// on the host's device, and its capture staged for recordUploads() (impostor_atlas.h): the
// capture crowd's batches' records and default blocks written, the capture program's pipeline
// made for the character's mesh.
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
  const BakedPalette& palette = *c.palette_source;
  const uint32_t sub_meshes = uint32_t(c.sub_meshes.size());
  // The atlas is an image and a colour attachment, the capture's depth an attachment, drawn
  // through one viewport.
  const si::detail::ImpostorSide sides[] = {{m.max_image_size, "maxImageDimension2D"},
                                            {m.max_framebuffer_size, "maxFramebufferWidth/Height"},
                                            {m.max_viewport_size, "maxViewportDimensions"}};
  si::detail::ImpostorPlan plan;
  const Status planned = si::detail::planImpostor(
      palette, sub_meshes, desc, Span<const si::detail::ImpostorSide>(sides, std::size(sides)),
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
  // The clip table: the clips, then every cell's covered rectangle at every level, which the
  // Vulkan back-end does not measure (si::gl reads the atlas back, and a guest waits for no
  // submission): the whole cell (the quads a little larger, the image the same).
  const std::vector<uint32_t> whole_cells(size_t(plan.cells) * plan.levels, 0xFFFF0000u);
  const std::vector<uint32_t> table = si::detail::impostorClipTable(plan, whole_cells);
  // The dynamic bindings' ranges read past their offsets: a block's worth past the end.
  const VkDeviceSize staging_bytes = table_at + table.size() * 4 + kRecordsRange;

  const auto fail = [&](Status why) {
    releaseImpostorCapture(&m.objects, &capture);
    return why;
  };
  ImpostorAtlas atlas;
  s = m.objects.createImage(plan.info.width, plan.info.height, ImpostorAtlas::kLayers, plan.levels,
                            VK_FORMAT_R8G8B8A8_UNORM, true, "the impostor atlas", &atlas.image,
                            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
  if (s.isOk())
    s = m.objects.createBuffer(
        table.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
        false, "the impostor clip table", &atlas.clips);
  if (s.isOk())
    s = m.objects.createImage(plan.info.width, plan.info.height, 1, 1,
                              ImpostorAtlas::kCaptureDepthFormat, false,
                              "the impostor capture's depth", &capture.depth,
                              VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT);
  for (uint32_t k = 0; k < ImpostorAtlas::kLayers && s.isOk(); ++k) {
    auto v = vkStruct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
    v.image = atlas.image.image;
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
  const uint32_t no_custom_layers = 0;
  writeDefault(staging + defaults_at, program.fragment_reflection, "u_custom_layers",
               &no_custom_layers, 4);
  writeDefault(staging + defaults_at, program.fragment_reflection, "u_light_direction",
               &m.desc.light_direction, 12);
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

  // The atlas's numbers, as si::gl's ImpostorAtlas holds them.
  atlas.clip_count = uint32_t(plan.clips.size());
  atlas.columns = plan.columns;
  atlas.rows = plan.rows;
  atlas.azimuths = plan.azimuths;
  atlas.elevations = uint32_t(plan.elevations_degrees.size());
  std::copy(std::begin(plan.elevations_radians), std::end(plan.elevations_radians),
            std::begin(atlas.elevations_radians));
  atlas.frame_stride_texels = palette.layout.frame_stride_texels;
  atlas.centre = plan.centre;
  atlas.cell_units = plan.cell_units;
  atlas.cell_texels = plan.cell;
  // A rebuild: the host has waited for the device's work on the old atlas (renderer.h).
  releaseImpostorAtlas(&m.objects, &c.impostor);
  releaseImpostorCapture(&m.objects, &c.capture);
  c.impostor = atlas;
  c.capture = std::move(capture);
  return Status::ok();
}

}  // namespace si::vk
