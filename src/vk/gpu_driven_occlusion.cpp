// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's occlusion culling: the depth pyramid of the host's depth and the second
// phase's passes (gpu_driven_views.h).
#include <cstring>

#include "vk/gpu_driven_views.h"
#include "vk/image_upload.h"

namespace si::vk::detail {

Status GpuDrivenViews::recordOcclusion(VkCommandBuffer cmd, uint32_t slot, FrameRegion region,
                                       uint32_t character, const CharacterResources& c,
                                       const CrowdView& view, const DepthSource& depth) {
  const auto found = views_.find({character, view.identity()});
  if (found == views_.end() || !found->second.passes_recorded || found->second.phase != 1)
    return {StatusCode::kInvalidArgument,
            "vk::Renderer::recordGpuDrivenOcclusion: the view's passes of this frame are no first "
            "phase of occlusion culling (GpuCulling::kOcclusion), or have their second"};
  View& v = found->second;
  VkDeviceSize cull_at = 0;
  Status s = region.take(kComputeDefaultsRange, &cull_at);
  if (!s.isOk()) return s;
  // The first phase's draws read the passes' output before the pyramid's and the second
  // phase's passes write it again; the last frame's second phase read the pyramid.
  recordReadsBeforeRewrites(cmd);
  // Window depth as the draws write it (their viewport's depth range is 0 to 1): the farthest
  // is the largest, or the smallest under reverse-Z.
  const bool far_is_max = v.camera.depth != DepthConvention::kReversedZeroToOne;
  PyramidContext ctx;
  ctx.passes = shared_.pyramid_passes;
  ctx.objects = shared_.objects;
  ctx.retirement = &retirement_;
  ctx.ring = shared_.ring;
  ctx.frames_in_flight = shared_.frames_in_flight;
  ctx.max_size = shared_.max_image_size;
  s = v.pyramid.record(cmd, slot, region, ctx, depth, far_is_max);
  if (!s.isOk()) return s;
  // This slot's passes' set with the pyramid bound (the slot's last frame is done with it).
  if (v.occlusion_pool == VK_NULL_HANDLE) {
    v.occlusion_sets.assign(shared_.frames_in_flight, VK_NULL_HANDLE);
    s = createDescriptorSets(shared_.objects->device(), shared_.objects->allocator(),
                             shared_.compute_layout->set_layout, shared_.compute_layout->bindings,
                             shared_.frames_in_flight, &v.occlusion_pool, v.occlusion_sets.data());
    if (!s.isOk()) {
      retirement_.retire(slot, &v.occlusion_pool);
      v.occlusion_sets.clear();
      return s;
    }
  }
  writePassSet(v.occlusion_sets[slot], &v, c, *v.crowd, v.pyramid.view(), VK_IMAGE_LAYOUT_GENERAL);
  // The second phase's cull uniforms: the first's, with the phase and the pyramid.
  uint8_t* block = region.mapped + cull_at;
  std::memcpy(block, region.mapped + v.defaults_at[0], size_t(kComputeDefaultsRange));
  const SpirvReflection& r = shared_.pass_modules[0]->compute_reflection;
  const uint32_t phase = 2;
  writeDefault(block, r, "u_occlusion_phase", &phase, 4);
  const glm::mat4 view_projection = v.camera.viewProjection();
  writeDefault(block, r, "u_view_proj", &view_projection[0][0], 64);
  const int32_t hiz_size[3] = {int32_t(v.pyramid.width()), int32_t(v.pyramid.height()),
                               int32_t(v.pyramid.levels())};
  writeDefault(block, r, "u_hiz_size", hiz_size, 12);
  const int32_t depth_mode[2] = {int32_t(v.camera.depth), far_is_max ? 1 : 0};
  writeDefault(block, r, "u_depth_mode", depth_mode, 8);
  const float depth_range[2] = {0.0f, 1.0f};
  writeDefault(block, r, "u_depth_range", depth_range, 8);
  v.defaults_at[0] = cull_at;
  v.phase = 2;
  v.phases = 2;
  return recordCullPasses(cmd, &v, v.occlusion_sets[slot], slot, 1, c);
}

}  // namespace si::vk::detail
