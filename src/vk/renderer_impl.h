// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// vk::Renderer's state, shared by its files: renderer.cpp (init, characters, uploads, frames),
// renderer_instanced.cpp (the instanced path's recordDraw), renderer_gpu_driven.cpp (the
// GPU-driven path's entry points) and renderer_impostor.cpp (impostor atlases).

#include <memory>
#include <vector>

#include "si/vk/renderer.h"
#include "vk/character_resources.h"
#include "vk/depth_pyramid.h"
#include "vk/device_objects.h"
#include "vk/gpu_driven_layout.h"
#include "vk/gpu_driven_views.h"
#include "vk/impostor_passes.h"
#include "vk/program_modules.h"
#include "vk/skinned_pipeline.h"

namespace si::vk {

struct Renderer::Impl {
  // Dynamic bindings of the instanced path's set: records, layers, previous layers, masks, the
  // two defaults.
  static constexpr uint32_t kMaxDynamicBindings = 6;
  using FrameRegion = detail::FrameRegion;
  using Character = detail::CharacterResources;

  RendererDesc desc;
  detail::DeviceObjects objects;
  VkDeviceSize ubo_alignment = 256;
  VkDeviceSize storage_alignment = 256;  // minStorageBufferOffsetAlignment (16 at least).
  uint32_t max_image_size = 0;           // maxImageDimension2D.
  uint32_t max_framebuffer_size = 0;     // maxFramebufferWidth and Height, the smaller.
  uint32_t max_viewport_size = 0;        // maxViewportDimensions, the smaller.
  // vulkanPrograms(), in its order: shaded, depth only and with motion vectors, for each mesh
  // variant (8 influences, vertex words); with RendererDesc::gpu_driven also the GPU-driven
  // draws and passes (left empty without).
  std::vector<detail::ProgramModules> programs;
  detail::SkinnedLayout layout;  // One set layout for drawCrowd's: the union of their declarations.
  // The GPU-driven path: its draws' set layout, its passes' layout and pipelines (cull,
  // commands, scatter; the depth pyramid's), what their unbuilt bindings are given, and its
  // views.
  detail::SkinnedLayout driven_layout;
  detail::ComputeLayout compute_layout;
  VkPipeline passes[3] = {};
  detail::GpuBuffer unbuilt;
  detail::GpuImage no_pyramid;
  detail::PyramidPasses pyramid_passes;  // Occlusion culling's depth pyramid.
  detail::ImpostorPasses impostor_passes;  // The impostor quads pass and draws.
  detail::GpuDrivenViews driven_views;
  VkSampler nearest = VK_NULL_HANDLE, linear = VK_NULL_HANDLE;
  detail::GpuBuffer ring;
  // Placeholders, one texel each, bound where a character has nothing of its own (every binding
  // of the set is written): the custom texture array (never sampled: u_custom_layers 0) and the
  // morph image of characters without targets (read only by the morph programs).
  detail::GpuImage custom, no_morphs;
  // The custom texel (4 bytes), the morph texel (at 16, 16 bytes), the pyramid's (at 32).
  detail::GpuBuffer placeholder_staging;
  bool placeholders_uploaded = false;
  std::vector<std::unique_ptr<Character>> characters;
  std::vector<detail::GpuBuffer> finished_staging;  // Freed by uploadsComplete().
  // Each slot's region: ring_bytes_per_frame rounded up to 256, so every region starts aligned.
  VkDeviceSize slot_bytes = 0;
  int32_t frame = -1;           // The slot beginFrame() started; -1 none.
  VkDeviceSize frame_used = 0;  // Bytes of its region written so far.

  VkDevice device() const { return objects.device(); }
  const VkAllocationCallbacks* allocator() const { return objects.allocator(); }
  // The frame slot's region of the ring.
  FrameRegion region() {
    return {static_cast<uint8_t*>(ring.mapped), VkDeviceSize(frame) * slot_bytes,
            desc.ring_bytes_per_frame, &frame_used, ubo_alignment};
  }
  // The checks every pass and draw makes (`call` names the entry point in errors): character
  // `id` exists and its uploads were recorded, and a frame was begun.
  Status checkFrame(const char* call, CharacterId id) const;
  // A draw's target: its mode, extent and depth test.
  static Status checkTarget(const char* call, const DrawTarget& target);
  // Creates the GPU-driven path's layouts, pipelines and placeholders (its programs loaded).
  Status initGpuDriven(const VkPhysicalDeviceLimits& limits);
};

}  // namespace si::vk
