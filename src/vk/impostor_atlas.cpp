// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The impostor atlas's capture recorded (drawn, resolved when supersampled, its mip chain and
// covered rectangles), and the atlas and capture destroyed.
#include "vk/impostor_atlas.h"

#include "vk/image_upload.h"

namespace si::vk::detail {

void recordImpostorCapture(VkCommandBuffer cmd, const ImpostorCapture& capture,
                           VkPipelineLayout pipeline_layout, VkBuffer vertices, VkBuffer indices,
                           const ImpostorPasses& passes, ImpostorAtlas* atlas) {
  const GpuImage& image = atlas->image;
  const bool resolved = capture.factor > 1;
  const uint32_t w = image.width * capture.factor, h = image.height * capture.factor;
  // The drawn layers (the atlas's level 0, or the supersampled capture's) attachments, the
  // atlas's other levels the blits' destinations, its level 0 supersampled the resolve's storage
  // image; the depth an attachment.
  recordImageBarrier(cmd, resolved ? capture.supersampled.image : image.image,
                     VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, ImpostorAtlas::kLayers,
                     {VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, 0,
                      VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                      VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT});
  if (image.levels > 1)
    recordImageBarrier(cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, image.levels - 1,
                       ImpostorAtlas::kLayers,
                       {VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                        VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                        VK_PIPELINE_STAGE_TRANSFER_BIT});
  if (resolved)
    recordImageBarrier(
        cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, ImpostorAtlas::kLayers,
        {VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, 0, VK_ACCESS_SHADER_WRITE_BIT,
         VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT});
  recordImageBarrier(
      cmd, capture.depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 1,
      {VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, 0,
       VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
       VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
       VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT});
  VkRenderingAttachmentInfo colors[ImpostorAtlas::kLayers];
  for (uint32_t k = 0; k < ImpostorAtlas::kLayers; ++k) {
    colors[k] = vkStruct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
    colors[k].imageView = capture.layers[k];
    colors[k].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colors[k].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    colors[k].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    colors[k].clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};
  }
  auto depth = vkStruct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
  depth.imageView = capture.depth.view;
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.clearValue.depthStencil = {1.0f, 0};
  auto rendering = vkStruct<VkRenderingInfo>(VK_STRUCTURE_TYPE_RENDERING_INFO);
  rendering.renderArea = {{0, 0}, {w, h}};
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = ImpostorAtlas::kLayers;
  rendering.pColorAttachments = colors;
  rendering.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &rendering);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, capture.pipeline);
  // Not flipped: clip y -1 at row 0, where OpenGL's capture puts it. The image is then OpenGL's
  // mirrored, and so is the winding: OpenGL's counter-clockwise front faces turn clockwise.
  const VkViewport viewport{0.0f, 0.0f, float(w), float(h), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, {w, h}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  vkCmdSetDepthCompareOp(cmd, VK_COMPARE_OP_LESS);
  vkCmdSetFrontFace(cmd, VK_FRONT_FACE_CLOCKWISE);
  vkCmdSetDepthBiasEnable(cmd, VK_FALSE);
  vkCmdSetDepthBias(cmd, 0.0f, 0.0f, 0.0f);
  const VkDeviceSize zero = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &vertices, &zero);
  vkCmdBindIndexBuffer(cmd, indices, 0, VK_INDEX_TYPE_UINT32);
  for (const ImpostorCapture::Draw& d : capture.draws) {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_layout, 0, 1,
                            &capture.set, uint32_t(d.offsets.size()), d.offsets.data());
    vkCmdDrawIndexed(cmd, d.index_count, d.instances, d.first_index, 0, 0);
  }
  vkCmdEndRendering(cmd);
  // Supersampled: one resolve dispatch of `layers` layers with the uniforms at `at`.
  const auto resolve = [&](uint32_t at, uint32_t layers) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, passes.resolve);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE,
                            passes.resolve_layout.pipeline_layout, 0, 1, &capture.resolve_set, 1,
                            &at);
    vkCmdDispatch(cmd, (image.width + 7) / 8, (image.height + 7) / 8, layers);
  };
  if (resolved) {
    // Every layer's means into level 0 (which the mip levels average), then level 0 the mip
    // chain's first source.
    recordImageBarrier(
        cmd, capture.supersampled.image, VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, ImpostorAtlas::kLayers,
        {VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
         VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
         VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT});
    resolve(capture.resolve_at[0], ImpostorAtlas::kLayers);
    recordImageBarrier(
        cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, ImpostorAtlas::kLayers,
        {VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_ACCESS_SHADER_WRITE_BIT,
         VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT});
  } else {
    // Level 0 the mip chain's first source.
    recordImageBarrier(
        cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, ImpostorAtlas::kLayers,
        {VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
         VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
         VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
         VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT});
  }
  recordMipChain(cmd, image,
                 VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  if (resolved) {
    // Level 0's surface layer again, as one material's (codes are not averaged: the impostor
    // fragment gathers level 0's), then every level read by the fragment and compute stages.
    recordImageBarrier(cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, ImpostorAtlas::kLayers,
                       {VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL, 0,
                        VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT});
    resolve(capture.resolve_at[1], 1);
    recordImageBarrier(
        cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, ImpostorAtlas::kLayers,
        {VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
         VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
         VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT});
  }
  const VkBufferCopy table{capture.table_at, 0, atlas->clips.size};
  vkCmdCopyBuffer(cmd, capture.staging.buffer, atlas->clips.buffer, 1, &table);
  // The covered rectangles: the extents cleared (minima to the largest word, maxima to 0), each
  // level's texels added, then the rectangles packed over the clip table's.
  const VkDeviceSize half = capture.extents.size / 2;
  vkCmdFillBuffer(cmd, capture.extents.buffer, 0, half, 0xFFFFFFFFu);
  vkCmdFillBuffer(cmd, capture.extents.buffer, half, half, 0u);
  recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  for (size_t k = 0; k < capture.coverage.size(); ++k) {
    const bool rects = k + 1 == capture.coverage.size();
    if (k == 0 || rects)
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, passes.coverage[rects ? 1 : 0]);
    if (rects)
      recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    const ImpostorCapture::CoveragePass& pass = capture.coverage[k];
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE,
                            passes.coverage_layout.pipeline_layout, 0, 1, &capture.coverage_set, 1,
                            &pass.defaults_at);
    vkCmdDispatch(cmd, pass.groups_x, pass.groups_y, 1);
  }
  recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT);
  atlas->captured = true;
}

void releaseImpostorCapture(DeviceObjects* objects, ImpostorCapture* capture) {
  const VkDevice device = objects->device();
  for (VkImageView v : capture->layers)
    if (v != VK_NULL_HANDLE) vkDestroyImageView(device, v, objects->allocator());
  if (capture->atlas_level0 != VK_NULL_HANDLE)
    vkDestroyImageView(device, capture->atlas_level0, objects->allocator());
  if (capture->resolve_pool != VK_NULL_HANDLE)
    vkDestroyDescriptorPool(device, capture->resolve_pool, objects->allocator());
  objects->destroy(&capture->supersampled);
  if (capture->pool != VK_NULL_HANDLE)
    vkDestroyDescriptorPool(device, capture->pool, objects->allocator());
  if (capture->coverage_pool != VK_NULL_HANDLE)
    vkDestroyDescriptorPool(device, capture->coverage_pool, objects->allocator());
  objects->destroy(&capture->extents);
  if (capture->pipeline != VK_NULL_HANDLE)
    vkDestroyPipeline(device, capture->pipeline, objects->allocator());
  objects->destroy(&capture->depth);
  objects->destroy(&capture->staging);
  *capture = ImpostorCapture();
}

void releaseImpostorAtlas(DeviceObjects* objects, ImpostorAtlas* atlas) {
  if (atlas->sampler != VK_NULL_HANDLE)
    vkDestroySampler(objects->device(), atlas->sampler, objects->allocator());
  objects->destroy(&atlas->image);
  objects->destroy(&atlas->clips);
  *atlas = ImpostorAtlas();
}

}  // namespace si::vk::detail
