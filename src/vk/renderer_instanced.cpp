// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// vk::Renderer's instanced path: si::gl's skinned program as SPIR-V, one instanced draw per
// batch of the view's CPU selection, its records, layer records, previous records and default
// blocks written into the frame slot's region of the ring; and the checks every draw and pass
// makes.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/str_cat.h"
#include "crowd/ring_frame.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_manager.h"
#include "si/vk/renderer.h"
#include "vk/draw_state.h"
#include "vk/renderer_impl.h"
#include "vk/spirv_reflect.h"
#include "vk/vulkan_programs.h"

namespace si::vk {

using si::detail::planRingFrame;
using si::detail::RingContents;
using si::detail::RingFrame;
using si::detail::strCat;
using si::detail::writeRingFrame;
using namespace si::vk::detail;

Status Renderer::Impl::checkFrame(const char* call, CharacterId id) const {
  if (id.index >= characters.size())
    return {StatusCode::kInvalidArgument, strCat(call, ": no character ", id.index)};
  if (!characters[id.index]->uploads_recorded)
    return {StatusCode::kInvalidArgument,
            strCat(call, ": the character's uploads were not recorded (recordUploads)")};
  if (frame < 0) return {StatusCode::kInvalidArgument, strCat(call, ": no beginFrame()")};
  return Status::ok();
}

Status Renderer::Impl::checkTarget(const char* call, const DrawTarget& target) {
  if (target.mode != DrawMode::kShaded && target.mode != DrawMode::kDepthOnly)
    return {StatusCode::kInvalidArgument, strCat(call, ": no draw mode ", int(target.mode))};
  if (target.extent.width == 0 || target.extent.height == 0)
    return {StatusCode::kInvalidArgument, strCat(call, ": an empty target extent")};
  if (target.offset.x < 0 || target.offset.y < 0 ||
      int64_t(target.offset.x) + target.extent.width > INT32_MAX ||
      int64_t(target.offset.y) + target.extent.height > INT32_MAX)
    return {StatusCode::kInvalidArgument,
            strCat(call, ": a target offset (", target.offset.x, ", ", target.offset.y,
                   ") that is negative or passes 2^31 with the extent")};
  if (target.depth_compare > VK_COMPARE_OP_ALWAYS && target.depth_compare != VK_COMPARE_OP_MAX_ENUM)
    return {StatusCode::kInvalidArgument,
            strCat(call, ": depth_compare ", int(target.depth_compare), " is no VkCompareOp")};
  return Status::ok();
}

Status Renderer::recordDraw(VkCommandBuffer cmd, const DrawTarget& target, CharacterId id,
                            const CrowdView& view, const InstanceBatcher& batcher,
                            const Camera& camera, DrawStats* stats) {
  if (!impl_) return {StatusCode::kInvalidArgument, "vk::Renderer::recordDraw: not initialized"};
  Impl& m = *impl_;
  Status checked = Impl::checkTarget("vk::Renderer::recordDraw", target);
  if (checked.isOk()) checked = m.checkFrame("vk::Renderer::recordDraw", id);
  if (!checked.isOk()) return checked;
  Impl::Character& c = *m.characters[id.index];
  if (batcher.capacityPerDraw() == 0 || batcher.capacityPerDraw() > kVulkanMaxInstances)
    return {StatusCode::kInvalidArgument,
            "vk::Renderer::recordDraw: the batcher was not initialized with batchLimits()"};
  if (view.crowd() != nullptr && view.crowd()->desc().impostor_lod != 0)
    return {StatusCode::kUnsupported,
            "vk::Renderer::recordDraw: the Vulkan back-end's instanced path does not draw "
            "impostors (CrowdDesc::impostor_lod) yet: the GPU-driven path does"};
  const bool depth_only = target.mode == DrawMode::kDepthOnly;
  // Motion vectors: shaded draws of a renderer with a motion format (depth-only ones write none).
  const bool motion = !depth_only && m.desc.motion_format != VK_FORMAT_UNDEFINED;
  if (motion && !view.desc().previous_records)
    return {StatusCode::kInvalidArgument,
            "vk::Renderer::recordDraw: motion vectors (RendererDesc::motion_format) need a crowd "
            "that keeps its previous records (CrowdDesc::previous_records; a view: "
            "CrowdViewDesc::previous_records)"};
  // Layered animation: the overlays composed on their masks in the vertex stage. A 2D blend's
  // third and fourth clips need si::gl's layer compose pass.
  const bool layers = !view.layerRecords().empty();
  if (layers && !view.extraLayerRecords().empty())
    return {StatusCode::kUnsupported,
            "vk::Renderer::recordDraw: the Vulkan back-end does not draw 2D blends (their third "
            "and fourth clips, CrowdView::extraLayerRecords) yet"};
  const std::vector<int32_t> masks =
      layers ? layerMaskTable(view.crowd()->layerMasks()) : std::vector<int32_t>();
  if (masks.size() * 4 > kMaskRange)
    return {StatusCode::kLimitExceeded,
            strCat("vk::Renderer::recordDraw: the crowd's layer mask table (", masks.size() * 4,
                   " bytes) passes the ", kMaskRange, " bytes its binding gives it")};
  // The frame's region: this draw's records (with motion vectors each slot's previous-record
  // index and the previous records; with layers the layer records, and previous ones:
  // crowd/ring_frame.h) after the frame's earlier draws', the mask table, then the default
  // blocks (the fragment stage's once, the vertex stage's per batch).
  const VkDeviceSize region = VkDeviceSize(m.frame) * m.slot_bytes;
  const VkDeviceSize records_at = alignUp(m.frame_used, m.ubo_alignment);
  RingContents contents;
  contents.motion = motion;
  contents.layers = layers;
  const RingFrame plan = planRingFrame(batcher, view, uint32_t(m.ubo_alignment), contents, true);
  std::vector<DrawBatch> draws;
  const VkDeviceSize masks_at = alignUp(records_at + plan.end, m.storage_alignment);
  const VkDeviceSize defaults_at = alignUp(masks_at + masks.size() * 4, kDefaultsRange);
  const auto past_region = [&](VkDeviceSize need) {
    return Status(
        StatusCode::kLimitExceeded,
        strCat("vk::Renderer::recordDraw: the frame's records need ", need,
               " bytes, RendererDesc::ring_bytes_per_frame is ", m.desc.ring_bytes_per_frame));
  };
  if (defaults_at + kDefaultsRange > m.desc.ring_bytes_per_frame)
    return past_region(defaults_at + kDefaultsRange);
  uint8_t* ring = static_cast<uint8_t*>(m.ring.mapped) + region;
  Status s = writeRingFrame(batcher, view, plan, ring + records_at, size_t(plan.end), {}, &draws);
  if (!s.isOk()) return s;
  if (!masks.empty()) std::memcpy(ring + masks_at, masks.data(), masks.size() * 4);
  const VkDeviceSize end = defaults_at + kDefaultsRange * (1 + draws.size());
  if (end > m.desc.ring_bytes_per_frame) return past_region(end);
  m.frame_used = end;
  // The fragment stage's defaults, then each batch's camera and LOD.
  const VulkanKind kind = depth_only ? VulkanKind::kDepthOnly
                          : motion   ? VulkanKind::kMotion
                                     : VulkanKind::kShaded;
  const ProgramModules& program = m.programs[c.programs[layers ? 1 : 0][size_t(kind)]];
  writeFragmentDefaults(ring + defaults_at, program.fragment_reflection, m.desc.light_direction);
  const glm::mat4 vp = vulkanViewProjection(camera);
  // The vertex stage's members, looked up once for every batch.
  const SpirvReflection& vertex = program.vertex_reflection;
  const SpirvMember *vp_member = defaultMember(vertex, "u_view_projection"),
                    *lod_member = defaultMember(vertex, "u_lod"),
                    *slot_member = defaultMember(vertex, "u_batch_slot"),
                    *now_member = defaultMember(vertex, "u_motion_view_projection"),
                    *then_member = defaultMember(vertex, "u_previous_view_projection"),
                    *previous_member = defaultMember(vertex, "u_previous"),
                    *shift_member = defaultMember(vertex, "u_previous_shift");
  // Motion vectors: the view's update cameras (this one and the one before), where the
  // previous indices and records are in the ring (16-byte words from its start; an index
  // numbers records), and the fallback's shift for instances without a previous record.
  struct MotionDefaults {
    glm::mat4 now, then;
    glm::uvec3 previous;
    glm::vec3 shift;
  } md{};
  if (motion) {
    md.now = vulkanViewProjection(view.camera());
    md.then = vulkanViewProjection(view.previousCamera());
    md.previous = glm::uvec3(uint32_t((region + records_at + plan.previous_indices) / 16),
                             uint32_t((region + records_at + plan.previous_records) / 16),
                             uint32_t(kInstanceRecordSize / 16));
    md.shift = previousRecordShift(view);
  }
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                    c.pipelines[layers ? 1 : 0][size_t(kind)]);
  recordDrawState(cmd, target, camera);
  const VkDeviceSize zero = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &c.vertices.buffer, &zero);
  vkCmdBindIndexBuffer(cmd, c.indices.buffer, 0, VK_INDEX_TYPE_UINT32);
  DrawStats st;
  for (size_t k = 0; k < draws.size(); ++k) {
    const DrawBatch& d = draws[k];
    if (d.sub_mesh >= c.sub_meshes.size()) continue;
    const IndexRange range = c.lodRange(d.sub_mesh, d.lod);
    if (range.index_count == 0) continue;
    const VkDeviceSize vertex_at = defaults_at + kDefaultsRange * (1 + k);
    writeDefault(ring + vertex_at, vp_member, &vp[0][0], 64);
    const uint32_t lod = d.lod;
    writeDefault(ring + vertex_at, lod_member, &lod, 4);
    if (motion) {
      // Slots are numbered as the layer records are (previous_index.glsl).
      const uint32_t slot = d.layer_byte_offset / kLayerRecordSize;
      writeDefault(ring + vertex_at, slot_member, &slot, 4);
      writeDefault(ring + vertex_at, now_member, &md.now, 64);
      writeDefault(ring + vertex_at, then_member, &md.then, 64);
      writeDefault(ring + vertex_at, previous_member, &md.previous, 12);
      writeDefault(ring + vertex_at, shift_member, &md.shift, 12);
    }
    // Dynamic offsets in binding order: the records, the layer records and previous ones
    // (the region's start when the draw has none), the mask table, the vertex and the fragment
    // defaults.
    const VkDeviceSize layer_at =
        layers ? records_at + plan.layer_records + d.layer_byte_offset : VkDeviceSize(0);
    const VkDeviceSize previous_layer_at =
        layers && motion ? records_at + plan.previous_layers + d.layer_byte_offset
                         : VkDeviceSize(0);
    uint32_t offsets[Impl::kMaxDynamicBindings] = {};
    uint32_t count = 0;
    for (uint32_t b : m.layout.dynamic_bindings) {
      const VkDeviceSize at = b == kRecordsBinding          ? records_at + d.byte_offset
                              : b == kLayersBinding         ? layer_at
                              : b == kPreviousLayersBinding ? previous_layer_at
                              : b == kMaskBinding           ? masks_at
                              : b == kVertexDefaultsBinding ? vertex_at
                                                            : defaults_at;
      offsets[count++] = uint32_t(region + at);
    }
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m.layout.pipeline_layout, 0, 1,
                            &c.set, count, offsets);
    vkCmdDrawIndexed(cmd, range.index_count, d.instance_count, range.first_index, 0, 0);
    ++st.draw_calls;
    st.triangles += uint64_t(range.index_count / 3) * d.instance_count;
    st.instances += d.instance_count;
  }
  if (stats != nullptr) *stats = st;
  return Status::ok();
}

}  // namespace si::vk
