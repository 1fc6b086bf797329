// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's views drawn (the pre-skinned entries pulled from the ring, the others
// skinned in the vertex stage), and what their passes counted, read back.
#include <algorithm>

#include "gl/programs/cull_layout.h"
#include "vk/draw_state.h"
#include "vk/gpu_driven_views.h"

namespace si::vk::detail {

using si::detail::kBucketCountWord;
using si::detail::kCounterWords;
using si::detail::kFittedWord;
using si::detail::kImpostorsDrawnWord;
using si::detail::kMaxBuckets;
using si::detail::kThreadBaseWord;

Status GpuDrivenViews::recordDraw(VkCommandBuffer cmd, FrameRegion region, uint32_t character,
                                  const CharacterResources& c, const CrowdView& view,
                                  const DrawTarget& target, const glm::vec3& light_direction,
                                  DrawStats* stats) {
  const auto found = views_.find({character, view.identity()});
  if (found == views_.end() || !found->second.passes_recorded)
    return {StatusCode::kInvalidArgument,
            "vk::Renderer::recordGpuDrivenDraw: the view's passes were not recorded in this "
            "frame (recordGpuDrivenPasses)"};
  View& v = found->second;
  // Shaded, depth only, or shaded with motion vectors (colour attachment 1).
  const VulkanKind kind = target.mode == DrawMode::kDepthOnly ? VulkanKind::kDepthOnly
                          : shared_.motion                    ? VulkanKind::kMotion
                                                              : VulkanKind::kShaded;
  const size_t k = size_t(kind);
  const bool pulled = v.ring_vertices != 0;
  // Each draw's vertex and fragment defaults: the pre-skinned draw's, then the other's.
  VkDeviceSize at[2][2] = {};
  for (int d = pulled ? 0 : 1; d < 2; ++d)
    for (VkDeviceSize& a : at[d]) {
      Status s = region.take(kDefaultsRange, &a);
      if (!s.isOk()) return s;
    }
  const glm::mat4 vp = vulkanViewProjection(v.camera);
  recordDrawState(cmd, target, v.camera);
  const VkBuffer vertex_buffers[2] = {c.vertices.buffer, v.crowd->identity.buffer};
  const VkDeviceSize zeros[2] = {0, 0};
  vkCmdBindVertexBuffers(cmd, 0, 2, vertex_buffers, zeros);
  DrawStats st;
  for (int d = pulled ? 0 : 1; d < 2; ++d) {
    const ProgramModules& program =
        (*shared_.programs)[d == 0 ? c.pulled_programs[k] : c.driven_programs[v.layering][k]];
    uint8_t* vertex = region.mapped + at[d][0];
    writeDefault(vertex, program.vertex_reflection, "u_view_projection", &vp[0][0], 64);
    const uint32_t layout_words[2] = {0u, c.source_words};
    writeDefault(vertex, program.vertex_reflection, "u_layout", layout_words, 8);
    if (kind == VulkanKind::kMotion) {  // This frame's camera of the view and the previous one.
      writeDefault(vertex, program.vertex_reflection, "u_motion_view_projection",
                   &v.view_projection[0][0], 64);
      writeDefault(vertex, program.vertex_reflection, "u_previous_view_projection",
                   &v.previous_view_projection[0][0], 64);
    }
    writeDefault(region.mapped + at[d][1], program.fragment_reflection, "u_light_direction",
                 &light_direction, 12);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                      d == 0 ? c.pulled_pipelines[k] : c.driven_pipelines[v.layering][k]);
    // The pre-skinned draw indexes each list's own vertices; the other the mesh's.
    vkCmdBindIndexBuffer(cmd, d == 0 ? c.local_indices.buffer : c.indices.buffer, 0,
                         VK_INDEX_TYPE_UINT32);
    // Dynamic offsets in binding order: the vertex, then the fragment defaults.
    uint32_t offsets[kMaxDrawOffsets] = {};
    const uint32_t count =
        drawOffsets(shared_.draw_layout->dynamic_bindings, at[d][0], at[d][1], offsets);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                            shared_.draw_layout->pipeline_layout, 0, 1, &v.draw_set, count,
                            offsets);
    // Commands 0 to 255 skin in the vertex stage, from 256 on the pre-skinned ones.
    vkCmdDrawIndexedIndirect(cmd, v.commands.buffer, d == 0 ? VkDeviceSize(kMaxBuckets) * 20 : 0,
                             v.buckets, 20);
    ++st.draw_calls;
  }
  // The impostor bucket: the quads the impostor quads pass computed.
  if (v.impostor_lod != 0) {
    const Status s =
        recordImpostorDraw(cmd, region, v, c, kind == VulkanKind::kDepthOnly, light_direction);
    if (!s.isOk()) return s;
    ++st.draw_calls;
  }
  if (stats != nullptr) *stats = st;
  return Status::ok();
}

Status GpuDrivenViews::readCounts(uint32_t character, const CharacterResources& c,
                                  const CrowdView& view, GpuDrivenCounts* out) const {
  const auto found = views_.find({character, view.identity()});
  if (found == views_.end() || !found->second.counted)
    return {StatusCode::kInvalidArgument,
            "vk::Renderer::readGpuDrivenCounts: the view's passes were never recorded"};
  const View& v = found->second;
  GpuDrivenCounts n;
  const uint32_t subs = v.sub_meshes;
  // Each phase's counters (occlusion culling's second after its first), summed.
  for (uint32_t phase = 0; phase < v.phases; ++phase) {
    const uint32_t* counters =
        static_cast<const uint32_t*>(v.readback[v.passes_slot].mapped) + phase * kCounterWords;
    n.visible += counters[0];
    for (uint32_t b = 0; b < v.buckets; ++b) {
      const uint32_t instances = counters[kBucketCountWord + b];
      const IndexRange range = c.lodRange(b % subs, b / subs);
      if (v.impostor_lod != 0 && b == v.impostor_lod * subs) {
        // The impostor bucket: the quads the impostor quads pass kept, 2 triangles each.
        const uint32_t kept = std::min(instances, counters[kImpostorsDrawnWord]);
        n.instances += kept;
        n.triangles += uint64_t(2) * kept;
        n.impostors_left_out += instances - kept;
        continue;
      }
      n.instances += instances;
      n.triangles += uint64_t(range.index_count / 3) * instances;
      n.vertex_shader_instances += instances - counters[kFittedWord + b];
    }
    n.pre_skinned_vertices += counters[kThreadBaseWord + v.buckets];
  }
  *out = n;
  return Status::ok();
}

}  // namespace si::vk::detail
