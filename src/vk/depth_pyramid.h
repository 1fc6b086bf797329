// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Occlusion culling's depth pyramid on Vulkan, one per GPU-driven view: the host's depth (the
// view of it the host gives, single-sampled or multisampled) reduced by si::gl's passes
// (shaders/hiz.comp.glsl: level 0 from the depth, each pixel's farthest sample; then each level
// from the one below, each texel the farthest depth of the 2 x 2 texels it covers) into an R32F
// mip chain with power-of-two sides, which the cull pass's second phase reads
// (cull_occlusion.glsl). The image stays in VK_IMAGE_LAYOUT_GENERAL: written as storage, read by
// texelFetch.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "si/core/status.h"
#include "si/vk/renderer.h"
#include "vk/device_objects.h"
#include "vk/frame_slots.h"
#include "vk/gpu_driven_layout.h"
#include "vk/program_modules.h"

namespace si::vk::detail {

/// The pyramid passes' layout and pipelines, made once by the renderer.
struct PyramidPasses {
  ComputeLayout layout;  ///< The union of the three passes' descriptors.
  /// Level 0 from a depth, from a multisampled depth; a level from the one below.
  VkPipeline copy = VK_NULL_HANDLE, copy_multisample = VK_NULL_HANDLE, reduce = VK_NULL_HANDLE;
  const ProgramModules* copy_modules = nullptr;
  const ProgramModules* copy_multisample_modules = nullptr;
  const ProgramModules* reduce_modules = nullptr;
  VkSampler nearest = VK_NULL_HANDLE;  ///< The depth's (texelFetch: never filtered).
};

/// Makes `passes`' layout (the union of the three modules' descriptors) and pipelines.
/// kUnsupported naming a descriptor the pyramid does not fill; kBackend on a failed call (what
/// was made is in `out` either way).
Status createPyramidPasses(VkDevice device, const VkAllocationCallbacks* allocator,
                           const ProgramModules& copy, const ProgramModules& copy_multisample,
                           const ProgramModules& reduce, VkSampler nearest, PyramidPasses* out);
void destroyPyramidPasses(VkDevice device, const VkAllocationCallbacks* allocator,
                          PyramidPasses* passes);

/// What building a pyramid takes from the renderer.
struct PyramidContext {
  const PyramidPasses* passes = nullptr;
  DeviceObjects* objects = nullptr;
  FrameRetirement* retirement = nullptr;
  const GpuBuffer* ring = nullptr;  ///< The record ring: the passes' uniforms.
  uint32_t frames_in_flight = 1;
  uint32_t max_size = 4096;  ///< maxImageDimension2D.
};

class DepthPyramid {
 public:
  /// Records into `cmd` (outside rendering, in frame slot `slot`, the passes' uniforms in
  /// `region`) the pyramid of `depth`: the farthest depth, the largest where `far_is_max`, else
  /// the smallest (reverse-Z). Remakes the image when the extent changes (what it had retired
  /// into `slot`). The host made `depth`'s writes visible to compute shaders. kLimitExceeded
  /// for a level 0 past maxImageDimension2D or uniforms past the slot's region; kBackend on a
  /// failed call.
  Status record(VkCommandBuffer cmd, uint32_t slot, FrameRegion region, const PyramidContext& ctx,
                const DepthSource& depth, bool far_is_max);
  /// A view of every level, VK_IMAGE_LAYOUT_GENERAL (after record()).
  VkImageView view() const { return image_.view; }
  uint32_t width() const { return width_; }  ///< The depth's extent (level 0's texels from 0).
  uint32_t height() const { return height_; }
  uint32_t levels() const { return image_.levels; }
  /// Its image's bytes (levels of 4 bytes a texel).
  uint64_t bytes() const;
  /// Retires the image, its views and sets into `slot`.
  void retire(uint32_t slot, FrameRetirement* retirement);

 private:
  // Makes the image of `w` x `h` (level 0 the powers of two at least as large), its level views
  // and its sets; records its transition to VK_IMAGE_LAYOUT_GENERAL.
  Status make(VkCommandBuffer cmd, const PyramidContext& ctx, uint32_t w, uint32_t h);

  GpuImage image_;
  std::vector<VkImageView> level_views_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> copy_sets_;    // Per frame slot: the host's depth changes.
  std::vector<VkDescriptorSet> reduce_sets_;  // Per level from 1: level k - 1 into level k.
  uint32_t width_ = 0, height_ = 0;
};

}  // namespace si::vk::detail
