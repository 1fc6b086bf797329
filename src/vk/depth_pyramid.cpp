// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "vk/depth_pyramid.h"

#include <algorithm>

#include "core/str_cat.h"
#include "si_vk/vulkan_profile.h"
#include "vk/gpu_driven_layout.h"
#include "vk/image_upload.h"
#include "vk/spirv_reflect.h"

namespace si::vk::detail {

using si::detail::strCat;

namespace {

// hiz.comp.glsl's resources: the level written (and in the reduce pass the level read) as
// images 0 and 1, the depth as sampler 0.
constexpr uint32_t kLevelBinding = 0 + kImageBindingShift;
constexpr uint32_t kNextLevelBinding = 1 + kImageBindingShift;
constexpr uint32_t kDepthBinding = 0 + kSamplerBindingShift;

constexpr LayoutChange kLevelWritten{VK_IMAGE_LAYOUT_GENERAL,
                                     VK_IMAGE_LAYOUT_GENERAL,
                                     VK_ACCESS_SHADER_WRITE_BIT,
                                     VK_ACCESS_SHADER_READ_BIT,
                                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT};

// The images, the depth and the uniforms (the default block, dynamic).
bool pyramidBindingType(uint32_t b, DescriptorKind kind, VkDescriptorType* type) {
  if ((b == kLevelBinding || b == kNextLevelBinding) && kind == DescriptorKind::kStorageImage)
    *type = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  else if (b == kDepthBinding && kind == DescriptorKind::kCombinedImageSampler)
    *type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  else if (b == kComputeDefaultsBinding && kind == DescriptorKind::kUniformBuffer)
    *type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
  else
    return false;
  return true;
}

}  // namespace

Status createPyramidPasses(VkDevice device, const VkAllocationCallbacks* allocator,
                           const ProgramModules& copy, const ProgramModules& copy_multisample,
                           const ProgramModules& reduce, VkSampler nearest, PyramidPasses* out) {
  out->copy_modules = &copy;
  out->copy_multisample_modules = &copy_multisample;
  out->reduce_modules = &reduce;
  out->nearest = nearest;
  const ProgramModules* passes[] = {&copy, &copy_multisample, &reduce};
  Status s = createComputeLayout(device, allocator, Span<const ProgramModules* const>(passes, 3),
                                 pyramidBindingType, "the depth pyramid's passes", &out->layout);
  if (s.isOk())
    s = createComputePipeline(device, allocator, copy, out->layout.pipeline_layout, &out->copy);
  if (s.isOk())
    s = createComputePipeline(device, allocator, copy_multisample, out->layout.pipeline_layout,
                              &out->copy_multisample);
  if (s.isOk())
    s = createComputePipeline(device, allocator, reduce, out->layout.pipeline_layout, &out->reduce);
  return s;
}

void destroyPyramidPasses(VkDevice device, const VkAllocationCallbacks* allocator,
                          PyramidPasses* passes) {
  for (VkPipeline p : {passes->copy, passes->copy_multisample, passes->reduce})
    if (p != VK_NULL_HANDLE) vkDestroyPipeline(device, p, allocator);
  destroyComputeLayout(device, allocator, &passes->layout);
  *passes = PyramidPasses();
}

Status DepthPyramid::make(VkCommandBuffer cmd, const PyramidContext& ctx, uint32_t w, uint32_t h) {
  // Level 0 has power-of-two sides at least the depth's, so every level halves exactly (as
  // si::gl's pyramid: a texel never claims a depth nearer than any it covers).
  uint32_t pw = 1, ph = 1, levels = 1;
  while (pw < w) pw *= 2;
  while (ph < h) ph *= 2;
  if (std::max(pw, ph) > ctx.max_size)
    return {StatusCode::kLimitExceeded,
            strCat("vk::Renderer::recordGpuDrivenOcclusion: a depth of ", w, " x ", h,
                   " needs a pyramid of ", pw, " x ", ph, ", past maxImageDimension2D (",
                   ctx.max_size, ")")};
  while ((std::max(pw, ph) >> (levels - 1)) > 1) ++levels;
  DeviceObjects& objects = *ctx.objects;
  Status s =
      objects.createImage(pw, ph, 1, levels, VK_FORMAT_R32_SFLOAT, false,
                          "occlusion culling's depth pyramid", &image_, VK_IMAGE_USAGE_STORAGE_BIT);
  for (uint32_t level = 0; s.isOk() && level < levels; ++level) {
    auto v = vkStruct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
    v.image = image_.image;
    v.viewType = VK_IMAGE_VIEW_TYPE_2D;
    v.format = VK_FORMAT_R32_SFLOAT;
    v.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, level, 1, 0, 1};
    level_views_.push_back(VK_NULL_HANDLE);
    s = checkVk(vkCreateImageView(objects.device(), &v, objects.allocator(), &level_views_.back()),
                "vkCreateImageView (a depth pyramid level)");
  }
  // A set per frame slot for the copy, one per level past 0 for the reductions.
  const uint32_t slots = ctx.frames_in_flight;
  std::vector<VkDescriptorSet> sets(slots + levels - 1);
  if (s.isOk())
    s = createDescriptorSets(objects.device(), objects.allocator(), ctx.passes->layout.set_layout,
                             ctx.passes->layout.bindings, uint32_t(sets.size()), &pool_,
                             sets.data());
  if (!s.isOk()) return s;
  copy_sets_.assign(sets.begin(), sets.begin() + slots);
  reduce_sets_.assign(sets.begin() + slots, sets.end());
  // Every binding of every set (lavapipe reads each binding of a bound set, used or not): the
  // uniforms (the record ring: each dispatch's dynamic offset picks its own); a reduction's
  // level read and level written; the copy's level 0 (its depth written by record(), its second
  // level unused) and the pyramid where a reduction reads no depth.
  std::vector<VkDescriptorImageInfo> images(3 * sets.size());
  std::vector<VkWriteDescriptorSet> writes;
  const VkDescriptorBufferInfo uniforms{ctx.ring->buffer, 0, kComputeDefaultsRange};
  for (size_t k = 0; k < sets.size(); ++k) {
    const bool copy = k < slots;
    const uint32_t read = copy ? 0 : uint32_t(k - slots), written = copy ? 0 : read + 1;
    images[3 * k] = {VK_NULL_HANDLE, level_views_[read], VK_IMAGE_LAYOUT_GENERAL};
    images[3 * k + 1] = {VK_NULL_HANDLE, level_views_[written], VK_IMAGE_LAYOUT_GENERAL};
    images[3 * k + 2] = {ctx.passes->nearest, image_.view, VK_IMAGE_LAYOUT_GENERAL};
    for (const VkDescriptorSetLayoutBinding& b : ctx.passes->layout.bindings) {
      if (copy && b.binding == kDepthBinding) continue;
      auto write = vkStruct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
      write.dstSet = sets[k];
      write.dstBinding = b.binding;
      write.descriptorCount = 1;
      write.descriptorType = b.descriptorType;
      if (b.binding == kComputeDefaultsBinding)
        write.pBufferInfo = &uniforms;
      else
        write.pImageInfo = &images[3 * k + (b.binding == kLevelBinding       ? 0
                                            : b.binding == kNextLevelBinding ? 1
                                                                             : 2)];
      writes.push_back(write);
    }
  }
  vkUpdateDescriptorSets(objects.device(), uint32_t(writes.size()), writes.data(), 0, nullptr);
  recordImageBarrier(
      cmd, image_.image, VK_IMAGE_ASPECT_COLOR_BIT, 0, levels, 1,
      {VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, 0, VK_ACCESS_SHADER_WRITE_BIT,
       VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT});
  width_ = w;
  height_ = h;
  return Status::ok();
}

Status DepthPyramid::record(VkCommandBuffer cmd, uint32_t slot, FrameRegion region,
                            const PyramidContext& ctx, const DepthSource& depth, bool far_is_max) {
  const PyramidPasses& passes = *ctx.passes;
  const uint32_t w = depth.extent.width, h = depth.extent.height;
  if (image_.image == VK_NULL_HANDLE || w != width_ || h != height_) {
    retire(slot, ctx.retirement);
    const Status s = make(cmd, ctx, w, h);
    if (!s.isOk()) {
      retire(slot, ctx.retirement);
      return s;
    }
  }
  // Each dispatch's uniforms: the copy's, then one per reduction.
  const uint32_t levels = image_.levels;
  std::vector<VkDeviceSize> defaults_at(levels);
  for (VkDeviceSize& at : defaults_at) {
    const Status s = region.take(kComputeDefaultsRange, &at);
    if (!s.isOk()) return s;
  }
  // This slot's copy set: the host's depth (its view may change from frame to frame).
  const VkDescriptorImageInfo source{passes.nearest, depth.view, depth.layout};
  VkDescriptorSet copy_set = copy_sets_[slot];
  auto write = vkStruct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
  write.dstSet = copy_set;
  write.dstBinding = kDepthBinding;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  write.pImageInfo = &source;
  vkUpdateDescriptorSets(ctx.objects->device(), 1, &write, 0, nullptr);
  const int32_t far = far_is_max ? 1 : 0;
  const bool multisampled = depth.samples != VK_SAMPLE_COUNT_1_BIT;
  const SpirvReflection& copy_r =
      (multisampled ? passes.copy_multisample_modules : passes.copy_modules)->compute_reflection;
  const SpirvReflection& reduce_r = passes.reduce_modules->compute_reflection;
  const int32_t pw = int32_t(image_.width), ph = int32_t(image_.height);
  {
    uint8_t* block = region.mapped + defaults_at[0];
    const int32_t size[2] = {pw, ph}, source_size[2] = {int32_t(w), int32_t(h)};
    const int32_t samples = int32_t(depth.samples);
    writeDefault(block, copy_r, "u_size", size, 8);
    writeDefault(block, copy_r, "u_source_size", source_size, 8);
    writeDefault(block, copy_r, "u_far_is_max", &far, 4);
    writeDefault(block, copy_r, "u_samples", &samples, 4);
    const int32_t offset[2] = {depth.offset.x, depth.offset.y};
    writeDefault(block, copy_r, "u_source_offset", offset, 8);
  }
  const VkPipelineLayout layout = passes.layout.pipeline_layout;
  const auto dispatch = [&](VkPipeline pipeline, VkDescriptorSet set, VkDeviceSize at, int32_t nw,
                            int32_t nh) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    const uint32_t offset = uint32_t(at);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 1, &offset);
    vkCmdDispatch(cmd, uint32_t(nw + 7) / 8, uint32_t(nh + 7) / 8, 1);
  };
  dispatch(multisampled ? passes.copy_multisample : passes.copy, copy_set, defaults_at[0], pw, ph);
  int32_t lw = pw, lh = ph;
  for (uint32_t level = 1; level < levels; ++level) {
    recordImageBarrier(cmd, image_.image, VK_IMAGE_ASPECT_COLOR_BIT, level - 1, 1, 1,
                       kLevelWritten);
    const int32_t nw = std::max(1, lw / 2), nh = std::max(1, lh / 2);
    uint8_t* block = region.mapped + defaults_at[level];
    const int32_t size[2] = {nw, nh}, source_size[2] = {lw, lh};
    writeDefault(block, reduce_r, "u_size", size, 8);
    writeDefault(block, reduce_r, "u_source_size", source_size, 8);
    writeDefault(block, reduce_r, "u_far_is_max", &far, 4);
    dispatch(passes.reduce, reduce_sets_[level - 1], defaults_at[level], nw, nh);
    lw = nw, lh = nh;
  }
  // Every level written before the cull pass reads them.
  recordImageBarrier(cmd, image_.image, VK_IMAGE_ASPECT_COLOR_BIT, 0, levels, 1, kLevelWritten);
  return Status::ok();
}

uint64_t DepthPyramid::bytes() const {
  uint64_t total = 0;
  for (uint32_t level = 0; level < image_.levels; ++level)
    total +=
        uint64_t(std::max(1u, image_.width >> level)) * std::max(1u, image_.height >> level) * 4;
  return total;
}

void DepthPyramid::retire(uint32_t slot, FrameRetirement* retirement) {
  for (VkImageView& v : level_views_) retirement->retire(slot, &v);
  level_views_.clear();
  retirement->retire(slot, &image_);
  retirement->retire(slot, &pool_);
  copy_sets_.clear();
  reduce_sets_.clear();
  width_ = height_ = 0;
}

}  // namespace si::vk::detail
