// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's views: their life (frames, eviction, a frame thrown away), the crowd's
// state brought up to date, the passes recorded. Their buffers and sets:
// gpu_driven_view_buffers.cpp; their draws and counts: gpu_driven_draws.cpp; occlusion
// culling's second phase: gpu_driven_occlusion.cpp; motion vectors' drawn records and cameras:
// gpu_driven_motion.cpp.
#include "vk/gpu_driven_views.h"

#include <algorithm>
#include <cstring>
#include <iterator>

#include "core/str_cat.h"
#include "gl/programs/cull_layout.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/crowd/instance_record.h"
#include "si_vk/vulkan_profile.h"
#include "vk/draw_state.h"
#include "vk/image_upload.h"

namespace si::vk::detail {

using si::detail::drawnSlotsToMake;
using si::detail::kBucketCountWord;
using si::detail::kCommandWords;
using si::detail::kCounterWords;
using si::detail::kDispatchWord;
using si::detail::kDrawnBytes;
using si::detail::kMaxBuckets;
using si::detail::kSkinDispatchWord;
using si::detail::strCat;

void GpuDrivenViews::recordReadsBeforeRewrites(VkCommandBuffer cmd) {
  recordMemoryBarrier(cmd,
                      VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_INPUT_BIT |
                          VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      0, VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0);
}

void GpuDrivenViews::init(const DrivenShared& shared) {
  shared_ = shared;
  retirement_.init(shared.objects);
  crowds_.init(shared.objects, &retirement_, shared.max_storage_range, shared.frames_in_flight,
               shared.ring_bytes != 0);
}

void GpuDrivenViews::beginFrame(uint32_t slot) {
  retirement_.release(slot);
  ++frame_;
  for (auto& [key, v] : views_)
    if (v.passes_slot == slot) v.passes_recorded = false;
  if (shared_.idle_frames != 0 && frame_ > shared_.idle_frames) evictIdle(slot);
}

void GpuDrivenViews::evictIdle(uint32_t slot) {
  const uint64_t before = frame_ - shared_.idle_frames;
  std::vector<const DrivenCrowd*> kept;
  for (auto it = views_.begin(); it != views_.end();) {
    View& v = it->second;
    if (v.used >= before) {
      kept.push_back(v.crowd);
      ++it;
      continue;
    }
    const auto gone = it++;
    forget(slot, gone);
  }
  crowds_.evict(slot, before, kept);
}

void GpuDrivenViews::forget(uint32_t slot,
                            std::map<std::pair<uint32_t, uint64_t>, View>::iterator it) {
  View& v = it->second;
  retire(slot, &v);
  v.pyramid.retire(slot, &retirement_);
  retirement_.retire(slot, &v.drawn);
  for (GpuBuffer& b : v.staging) retirement_.retire(slot, &b);
  for (GpuBuffer& b : v.readback) retirement_.retire(slot, &b);
  views_.erase(it);
}

void GpuDrivenViews::retire(uint32_t slot, View* v) {
  for (GpuBuffer* b : v->buffers()) retirement_.retire(slot, b);
  retirement_.retire(slot, &v->pass_pool);
  retirement_.retire(slot, &v->draw_pool);
  retirement_.retire(slot, &v->occlusion_pool);
  retirement_.retire(slot, &v->quads);
  retirement_.retire(slot, &v->impostor_pool);
  v->impostor_sets[0] = v->impostor_sets[1] = VK_NULL_HANDLE;
  v->impostor_clips = VK_NULL_HANDLE;
  v->occlusion_sets.clear();
  v->pass_set = v->draw_set = VK_NULL_HANDLE;
  v->crowd = nullptr;
  v->capacity = 0;
}

Status GpuDrivenViews::recordPasses(VkCommandBuffer cmd, uint32_t slot, FrameRegion region,
                                    uint32_t character, const CharacterResources& c,
                                    const CrowdView& view, const Camera& camera, bool occlusion) {
  const CrowdManager& crowd = *view.crowd();
  const CrowdDesc& cd = crowd.desc();
  const uint32_t subs = cd.sub_mesh_count, lods = cd.lod_count, buckets = lods * subs;
  if (buckets > kMaxBuckets || subs > c.sub_meshes.size())
    return {StatusCode::kInvalidArgument,
            strCat("vk::Renderer::recordGpuDrivenPasses: ", subs, " sub-meshes x ", lods,
                   " LODs do not fit the character (", c.sub_meshes.size(),
                   " sub-meshes) or 256 buckets")};
  const uint32_t n = crowd.size();
  // The cull pass's groups in rows of at most maxComputeWorkGroupCount[0] (dispatch_index.glsl).
  const uint64_t groups = std::max<uint64_t>(1, (uint64_t(n) + 63) / 64);
  const uint32_t gx = uint32_t(std::min<uint64_t>(groups, shared_.max_groups_x));
  const uint64_t gy = (groups + gx - 1) / gx;
  if (gy > shared_.max_groups_y)
    return {StatusCode::kLimitExceeded,
            strCat("vk::Renderer::recordGpuDrivenPasses: ", n,
                   " instances need more compute "
                   "groups than maxComputeWorkGroupCount (",
                   shared_.max_groups_x, " x ", shared_.max_groups_y, ")")};
  // The passes' uniforms first: a full region refuses the frame before anything is recorded.
  // The cull, commands, scatter, pre-skinning, impostor quads and layer compose passes'.
  VkDeviceSize defaults_at[6] = {};
  for (VkDeviceSize& at : defaults_at) {
    Status s = region.take(kComputeDefaultsRange, &at);
    if (!s.isOk()) return s;
  }
  const auto key = std::make_pair(character, view.identity());
  View& v = views_[key];
  // Whatever the last frames' draws and passes read of the crowd's and the view's buffers is
  // read before these copies and passes write them (the host submits frames in order on one
  // queue).
  recordReadsBeforeRewrites(cmd);
  // The crowd's state, shared by its views: what changed since its last upload.
  DrivenCrowd* d = nullptr;
  Status s = crowds_.update(cmd, slot, character, c, crowd, &d, &last_upload_);
  bool drawn_remade = false;  // The sets bind the drawn records: made again with them.
  if (s.isOk() && shared_.motion) s = ensureDrawn(cmd, slot, &v, d->slots_needed, &drawn_remade);
  if (s.isOk() && (v.crowd != d || v.generation != d->generation || drawn_remade))
    s = reshape(cmd, &v, slot, c, *d, view);
  if (!s.isOk()) {
    forget(slot, views_.find(key));
    return s;
  }

  // 2D blends: the extra layers' first index (of the overlays and of the layer records), and of
  // the previous ones; 0 without.
  const uint32_t extras = d->extras ? v.capacity : 0u;
  const uint32_t previous_extras = d->extras && shared_.motion ? v.capacity : 0u;
  // The passes' uniforms: the same CullParams CrowdView::select() uses.
  const CullParams p = CrowdExport::cullParams(view, camera);
  uint8_t* ring = region.mapped;
  const uint32_t counts[4] = {n, lods, subs, c.frame_stride_texels};
  for (int pass = 0; pass < 3; ++pass)
    writeDefault(ring + defaults_at[pass], shared_.pass_modules[pass]->compute_reflection,
                 "u_counts", counts, 16);
  {
    const SpirvReflection& r = shared_.pass_modules[0]->compute_reflection;
    uint8_t* block = ring + defaults_at[0];
    writeDefault(block, r, "u_planes", p.planes.data(), 16, 6);
    const double position[3] = {camera.position.x, camera.position.y, camera.position.z};
    writeDefault(block, r, "u_camera", position, 24);
    const double clock = crowd.clockSeconds();
    writeDefault(block, r, "u_clock", &clock, 8);
    // CrowdDesc::impostor_lod (0: none): an instance there joins one bucket, sub-mesh 0's.
    writeDefault(block, r, "u_impostor_lod", &cd.impostor_lod, 4);
    const float params[4] = {p.radius, p.max_distance_radii, p.hysteresis, 0.0f};
    writeDefault(block, r, "u_params", params, 16);
    writeDefault(block, r, "u_lines", p.lod_lines, 4, 7);
    writeDefault(block, r, "u_anim_lod", &p.animation_lod_start, 4);
    writeDefault(block, r, "u_anim_step", &p.animation_step_seconds, 8);
    writeDefault(block, r, "u_lod_bias", &p.lod_bias, 4);
    uint32_t drawn_parts[8] = {};
    for (uint32_t lod = 0; lod < lods && lod < 8; ++lod)
      for (uint32_t sm = 0; sm < subs; ++sm)
        if (c.lodRange(sm, lod).index_count > 0) drawn_parts[lod] |= 1u << sm;
    writeDefault(block, r, "u_drawn_parts", drawn_parts, 4, 8);
    // Occlusion culling's first phase: the instances visible at the end of the last frame.
    const uint32_t phase = occlusion ? 1u : 0u;
    writeDefault(block, r, "u_occlusion_phase", &phase, 4);
    if (shared_.motion) {
      // Motion vectors: each visible instance's previous record, what the view drew of it at
      // the crowd's previous frame (the drawn records' other parity), or its record moved by
      // the cameras' shift (si::previousRecordShift).
      updateMotionCameras(&v, d->frame, camera);
      const uint32_t on = 1, frame[2] = {uint32_t(d->frame), v.drawn_slots};
      writeDefault(block, r, "u_motion", &on, 4);
      writeDefault(block, r, "u_frame", frame, 8);
      const glm::vec3 shift = previousRecordShift(v.position, v.previous_position);
      writeDefault(block, r, "u_camera_shift", &shift[0], 12);
    }
    // Layers: each visible instance's layer record written beside its record (and a 2D blend's
    // two extra layer records after them, from u_extras).
    const uint32_t layers = d->layers ? 1u : 0u;
    writeDefault(block, r, "u_layers", &layers, 4);
    writeDefault(block, r, "u_extras", &extras, 4);
    writeDefault(block, r, "u_previous_extras", &previous_extras, 4);
  }
  {
    const SpirvReflection& r = shared_.pass_modules[1]->compute_reflection;
    uint8_t* block = ring + defaults_at[1];
    // The impostor level's bucket, or none (past the buckets).
    const uint32_t impostor_bucket = cd.impostor_lod != 0 ? cd.impostor_lod * subs : 0xFFFFFFFFu;
    writeDefault(block, r, "u_ring_vertices", &v.ring_vertices, 4);
    writeDefault(block, r, "u_max_groups_x", &shared_.max_groups_x, 4);
    writeDefault(block, r, "u_impostor_bucket", &impostor_bucket, 4);
  }
  // Layered animation: per vertex, or composed by the layer compose pass (2D blends) over the
  // visible instances (at most n), its groups in rows as the cull pass's.
  v.layering = !d->layers ? kNoLayers : d->extras ? kComposedLayers : kLayersPerVertex;
  if (v.layering == kComposedLayers) {
    const uint32_t lanes = d->shape.lanes();
    const uint64_t compose_groups = std::max<uint64_t>(1, (uint64_t(n) * lanes + 63) / 64);
    v.compose_groups_x = uint32_t(std::min<uint64_t>(compose_groups, shared_.max_groups_x));
    const uint64_t compose_y = (compose_groups + v.compose_groups_x - 1) / v.compose_groups_x;
    if (lanes == 0 || compose_y > shared_.max_groups_y) {
      forget(slot, views_.find(key));
      return {lanes == 0 ? StatusCode::kUnsupported : StatusCode::kLimitExceeded,
              strCat("vk::Renderer::recordGpuDrivenPasses: a 2D blend's layers are composed in a "
                     "pass of ",
                     lanes, " invocations an instance, which ", n,
                     " instances pass maxComputeWorkGroupCount with (or masks that hold no joint "
                     "and no morph target: nothing to compose)")};
    }
    v.compose_groups_y = uint32_t(compose_y);
    const SpirvReflection& compose =
        (*shared_.programs)[c.compose_programs[shared_.motion]].compute_reflection;
    const uint32_t compose_words[3] = {n, extras, previous_extras};
    writeDefault(ring + defaults_at[5], compose, "u_compose", compose_words, 12);
  }
  const SpirvReflection& skin =
      (*shared_.programs)[c.skin_programs[v.layering][shared_.motion]].compute_reflection;
  writeDefault(ring + defaults_at[3], skin, "u_counts", counts, 16);
  const uint32_t layout_words[2] = {0u, c.source_words};
  writeDefault(ring + defaults_at[3], skin, "u_layout", layout_words, 8);
  // Impostors: the quads pass's quads, sets and uniforms (the renderer checked the atlas).
  v.impostor_lod = cd.impostor_lod;
  if (v.impostor_lod != 0) {
    s = ensureImpostors(slot, &v, c);
    if (!s.isOk()) {
      forget(slot, views_.find(key));
      return s;
    }
    writeImpostorDefaults(ring + defaults_at[4], v, c, camera);
  }
  std::copy(std::begin(defaults_at), std::end(defaults_at), std::begin(v.defaults_at));
  v.groups_x = gx;
  v.groups_y = uint32_t(gy);
  v.phase = occlusion ? 1 : 0;
  v.phases = 1;
  s = recordCullPasses(cmd, &v, v.pass_set, slot, 0, c);
  if (!s.isOk()) return s;
  v.camera = camera;
  v.passes_recorded = true;
  v.passes_slot = slot;
  v.used = frame_;
  GpuDrivenCrowds::touch(d, frame_);
  return Status::ok();
}

Status GpuDrivenViews::recordCullPasses(VkCommandBuffer cmd, View* view, VkDescriptorSet set,
                                        uint32_t slot, uint32_t phase_index,
                                        const CharacterResources& c) {
  View& v = *view;
  // Zero the visible count and the bucket counts.
  vkCmdFillBuffer(cmd, v.counters.buffer, 0, VkDeviceSize(kBucketCountWord + kMaxBuckets) * 4, 0);
  recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  VkPipelineLayout layout = shared_.compute_layout->pipeline_layout;
  const auto bind = [&](int pass) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE,
                      pass < 3    ? shared_.passes[pass]
                      : pass == 3 ? c.skin_pipelines[v.layering][shared_.motion]
                                  : c.compose_pipelines[shared_.motion]);
    const uint32_t offset = uint32_t(v.defaults_at[pass]);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 1, &offset);
  };
  bind(0);
  vkCmdDispatch(cmd, v.groups_x, v.groups_y, 1);
  recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  bind(1);
  vkCmdDispatch(cmd, 1, 1, 1);
  recordMemoryBarrier(
      cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
  bind(2);
  vkCmdDispatchIndirect(cmd, v.counters.buffer, VkDeviceSize(kDispatchWord) * 4);
  if (v.layering == kComposedLayers) {
    // The layer compose pass: each visible instance's masked rows, read by the skinning.
    recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    bind(5);
    vkCmdDispatch(cmd, v.compose_groups_x, v.compose_groups_y, 1);
  }
  if (v.ring_vertices != 0) {
    // Every pre-skinned entry's vertices into the ring (the groups the commands pass counted).
    recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    bind(3);
    vkCmdDispatchIndirect(cmd, v.counters.buffer, VkDeviceSize(kSkinDispatchWord) * 4);
  }
  if (v.impostor_lod != 0) recordImpostorQuads(cmd, v);
  // The counters into this slot's readback (readCounts, after the host's wait), each phase's
  // after the one before.
  if (v.readback.size() < shared_.frames_in_flight) v.readback.resize(shared_.frames_in_flight);
  const VkDeviceSize counter_bytes = VkDeviceSize(kCounterWords) * 4;
  if (v.readback[slot].buffer == VK_NULL_HANDLE) {
    Status made =
        shared_.objects->createBuffer(2 * counter_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true,
                                      "the GPU-driven counters' readback", &v.readback[slot]);
    if (!made.isOk()) return made;
  }
  recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  const VkBufferCopy counted{0, phase_index * counter_bytes, counter_bytes};
  vkCmdCopyBuffer(cmd, v.counters.buffer, v.readback[slot].buffer, 1, &counted);
  recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
  v.counted = true;
  // The draws read the commands, entry indices, entries, records, visible list and ring.
  recordMemoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_INPUT_BIT |
                          VK_PIPELINE_STAGE_VERTEX_SHADER_BIT,
                      VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT |
                          VK_ACCESS_SHADER_READ_BIT);
  return Status::ok();
}

void GpuDrivenViews::discardFrame(uint32_t slot) {
  // A crowd updated in this frame (bit `used`) was copied in by the thrown-away command buffer.
  std::vector<const DrivenCrowd*> forgotten;
  crowds_.forgetUpdatedAt(slot, frame_, &forgotten);
  for (auto it = views_.begin(); it != views_.end();) {
    const View& v = it->second;
    const bool recorded = v.passes_recorded && v.passes_slot == slot;
    const bool orphaned = std::find(forgotten.begin(), forgotten.end(), v.crowd) != forgotten.end();
    if (!recorded && !orphaned) {
      ++it;
      continue;
    }
    const auto gone = it++;
    forget(slot, gone);
  }
  retirement_.holdForCycle(slot, shared_.frames_in_flight);
}

GpuDrivenMemory GpuDrivenViews::memory() const {
  GpuDrivenMemory m;
  m.crowds = crowds_.size();
  m.views = uint32_t(views_.size());
  m.crowd_bytes = crowds_.deviceBytes();
  for (const auto& [key, v] : views_) {
    for (const GpuBuffer* b : v.buffers()) m.view_bytes += b->size;
    m.view_bytes += v.pyramid.bytes() + v.drawn.size + v.quads.size;
  }
  return m;
}

void GpuDrivenViews::release() {
  while (!views_.empty()) forget(0, views_.begin());
  crowds_.release();
  retirement_.releaseAll();
}

}  // namespace si::vk::detail
