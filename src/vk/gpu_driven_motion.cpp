// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's motion vectors: a view's drawn records and its cameras
// (gpu_driven_views.h).
#include <cstring>

#include "core/str_cat.h"
#include "gl/programs/cull_layout.h"
#include "vk/draw_state.h"
#include "vk/gpu_driven_views.h"
#include "vk/image_upload.h"

namespace si::vk::detail {

using si::detail::drawnSlotsToMake;
using si::detail::kDrawnBytes;
using si::detail::strCat;

Status GpuDrivenViews::ensureDrawn(VkCommandBuffer cmd, uint32_t slot, View* v, uint32_t slots,
                                   bool* remade) {
  *remade = false;
  if (slots <= v->drawn_slots) return Status::ok();
  const uint32_t grown = drawnSlotsToMake(slots, v->drawn_slots, shared_.max_storage_range);
  const VkDeviceSize bytes = VkDeviceSize(grown) * 2 * kDrawnBytes;
  if (bytes > shared_.max_storage_range)
    return {StatusCode::kLimitExceeded,
            strCat("vk::Renderer::recordGpuDrivenPasses: motion vectors keep ", bytes,
                   " bytes of drawn records for ", grown,
                   " handle slots, past maxStorageBufferRange (", shared_.max_storage_range, ")")};
  retirement_.retire(slot, &v->drawn);
  v->drawn_slots = 0;
  Status s = shared_.objects->createBuffer(
      bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false,
      "motion vectors: a view's drawn records", &v->drawn);
  if (!s.isOk()) return s;
  // Zeroed: no tag names a frame's instance until the passes draw it.
  vkCmdFillBuffer(cmd, v->drawn.buffer, 0, VK_WHOLE_SIZE, 0);
  recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  v->drawn_slots = grown;
  *remade = true;
  return Status::ok();
}

void GpuDrivenViews::updateMotionCameras(View* v, uint64_t frame, const Camera& camera) {
  if (v->motion_frame != frame) {  // The view's first passes of this crowd frame.
    v->previous_known = v->camera_frame == frame - 1 && v->camera_frame != 0;
    v->previous_position = v->position;
    v->previous_view_projection = v->view_projection;
    v->motion_frame = frame;
  }
  v->position = camera.position;
  v->view_projection = vulkanViewProjection(camera);
  v->camera_frame = frame;
  if (!v->previous_known) {  // No previous frame: no camera motion either.
    v->previous_position = v->position;
    v->previous_view_projection = v->view_projection;
  }
}

}  // namespace si::vk::detail
