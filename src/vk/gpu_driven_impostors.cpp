// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's impostors (si::gl's drawImpostorsIndirect): each view's quads, the impostor
// quads pass after its scatter pass, and the impostor draw after its meshes'.
#include <algorithm>
#include <cmath>

#include "core/str_cat.h"
#include "gl/programs/cull_layout.h"
#include "vk/draw_state.h"
#include "vk/gpu_driven_views.h"
#include "vk/image_upload.h"

namespace si::vk::detail {

using si::detail::kImpostorDispatchWord;
using si::detail::kImpostorQuadBytes;
using si::detail::kMaxBuckets;

namespace {

// The impostor draw's command in the commands buffer (after the vertex-stage and pre-skinned
// draws' 20-byte commands: si::gl's kImpostorCommand).
constexpr VkDeviceSize kImpostorCommandBytes = VkDeviceSize(kMaxBuckets) * 20 * 2;

}  // namespace

Status GpuDrivenViews::ensureImpostors(uint32_t slot, View* v, const CharacterResources& c) {
  const ImpostorPasses& passes = *shared_.impostors;
  const VkDeviceSize quad_bytes = std::max<VkDeviceSize>(v->capacity, 1) * kImpostorQuadBytes;
  if (v->impostor_pool != VK_NULL_HANDLE && v->quads.size >= quad_bytes &&
      v->impostor_clips == c.impostor.clips.buffer)
    return Status::ok();
  retirement_.retire(slot, &v->quads);
  retirement_.retire(slot, &v->impostor_pool);
  v->impostor_sets[0] = v->impostor_sets[1] = VK_NULL_HANDLE;
  v->impostor_clips = VK_NULL_HANDLE;
  if (quad_bytes > shared_.max_storage_range)
    return {
        StatusCode::kLimitExceeded,
        si::detail::strCat("vk::Renderer::recordGpuDrivenPasses: the impostor quads (", quad_bytes,
                           " bytes) pass maxStorageBufferRange ", shared_.max_storage_range)};
  Status s = shared_.objects->createBuffer(quad_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                                           "the impostor quads", &v->quads);
  // One pool for both sets: the quads pass's bindings and the draw's.
  std::vector<VkDescriptorSetLayoutBinding> all = passes.quads_layout.bindings;
  all.insert(all.end(), passes.draw_layout.bindings.begin(), passes.draw_layout.bindings.end());
  if (s.isOk())
    s = createDescriptorSets(shared_.objects->device(), shared_.objects->allocator(),
                             {passes.quads_layout.set_layout, passes.draw_layout.set_layout}, all,
                             &v->impostor_pool, v->impostor_sets);
  if (!s.isOk()) return s;
  std::vector<VkWriteDescriptorSet> writes;
  std::vector<VkDescriptorBufferInfo> buffers(all.size());
  const VkDescriptorImageInfo atlas{c.impostor.sampler, c.impostor.image.view,
                                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  const VkDescriptorImageInfo custom{shared_.linear, shared_.custom->view,
                                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  size_t at = 0;
  for (int set = 0; set < 2; ++set) {
    const std::vector<VkDescriptorSetLayoutBinding>& bindings =
        set == 0 ? passes.quads_layout.bindings : passes.draw_layout.bindings;
    for (const VkDescriptorSetLayoutBinding& binding : bindings) {
      const uint32_t b = binding.binding;
      auto w = vkStruct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
      w.dstSet = v->impostor_sets[set];
      w.dstBinding = b;
      w.descriptorCount = 1;
      w.descriptorType = binding.descriptorType;
      if (b == kImpostorAtlasBinding) {
        w.pImageInfo = &atlas;
      } else if (b == kCustomBinding) {
        w.pImageInfo = &custom;
      } else {
        const GpuBuffer* buffer = b == kCountersBinding        ? &v->counters
                                  : b == kDrivenRecordsBinding ? &v->records
                                  : b == kDrivenEntriesBinding ? &v->entries
                                  : b == kDrivenVisibleBinding ? &v->visible
                                  : b == kCommandsBinding      ? &v->commands
                                  : b == kImpostorClipsBinding ? &c.impostor.clips
                                  : b == kImpostorQuadsBinding ? &v->quads
                                                               : shared_.ring;
        const VkDeviceSize range = b == kComputeDefaultsBinding ? kComputeDefaultsRange
                                   : b == kVertexDefaultsBinding || b == kFragmentDefaultsBinding
                                       ? kDefaultsRange
                                       : VK_WHOLE_SIZE;
        buffers[at] = {buffer->buffer, 0, range};
        w.pBufferInfo = &buffers[at++];
      }
      writes.push_back(w);
    }
  }
  vkUpdateDescriptorSets(shared_.objects->device(), uint32_t(writes.size()), writes.data(), 0,
                         nullptr);
  v->impostor_clips = c.impostor.clips.buffer;
  return Status::ok();
}

void GpuDrivenViews::writeImpostorDefaults(uint8_t* block, const View& v,
                                           const CharacterResources& c,
                                           const Camera& camera) const {
  const SpirvReflection& r = shared_.impostors->quads_program->compute_reflection;
  const ImpostorAtlas& a = c.impostor;
  const glm::mat4 vp = vulkanViewProjection(camera);
  writeDefault(block, r, "u_view_projection", &vp[0][0], 64);
  const glm::uvec4 grid = a.grid(), counts = a.counts();
  const glm::vec4 cell = a.cell();
  writeDefault(block, r, "u_impostor_grid", &grid[0], 16);
  writeDefault(block, r, "u_impostor_counts", &counts[0], 16);
  writeDefault(block, r, "u_impostor_elevations", a.elevations_radians, 16);
  writeDefault(block, r, "u_impostor_cell", &cell[0], 16);
  const glm::vec4 viewer = si::detail::impostorViewer(camera);
  writeDefault(block, r, "u_viewer", &viewer[0], 16);
  // The viewport the passes know is the camera's (Camera::viewport_height_pixels, as wide as its
  // projection's aspect): half of it in pixels. On single-sampled targets the quads that cover
  // none of its pixel centres are left out (u_small_quads), as si::gl leaves them out; with
  // every cell's rectangle whole (renderer_impostor.cpp) the levels it picks do not matter.
  const float height = camera.viewport_height_pixels;
  const float aspect = camera.projection[0][0] != 0.0f
                           ? std::abs(camera.projection[1][1] / camera.projection[0][0])
                           : 1.0f;
  const bool known = height > 0.0f && std::isfinite(height * aspect);
  const glm::vec3 texels =
      known ? glm::vec3(0.5f * height * aspect, 0.5f * height, float(a.cell_texels))
            : glm::vec3(1.0f, 1.0f, float(a.cell_texels));
  writeDefault(block, r, "u_impostor_texels", &texels[0], 12);
  const uint32_t bucket = v.impostor_lod * v.sub_meshes;
  const uint32_t small_quads = known && shared_.single_sampled ? 1u : 0u;
  writeDefault(block, r, "u_impostor_bucket", &bucket, 4);
  writeDefault(block, r, "u_small_quads", &small_quads, 4);
}

void GpuDrivenViews::recordImpostorQuads(VkCommandBuffer cmd, const View& v) const {
  const ImpostorPasses& passes = *shared_.impostors;
  recordMemoryBarrier(
      cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, passes.quads);
  const uint32_t offset = uint32_t(v.defaults_at[4]);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, passes.quads_layout.pipeline_layout,
                          0, 1, &v.impostor_sets[0], 1, &offset);
  vkCmdDispatchIndirect(cmd, v.counters.buffer, VkDeviceSize(kImpostorDispatchWord) * 4);
}

Status GpuDrivenViews::recordImpostorDraw(VkCommandBuffer cmd, FrameRegion region, const View& v,
                                          const CharacterResources& c, bool depth_only,
                                          const glm::vec3& light_direction) const {
  const ImpostorPasses& passes = *shared_.impostors;
  const int k = depth_only ? 1 : 0;
  VkDeviceSize vertex_at = 0, fragment_at = 0;
  Status s = region.take(kDefaultsRange, &vertex_at);
  if (s.isOk()) s = region.take(kDefaultsRange, &fragment_at);
  if (!s.isOk()) return s;
  const ProgramModules& program = *passes.draw_programs[k];
  uint8_t* vertex = region.mapped + vertex_at;
  const glm::mat4 vp = vulkanViewProjection(v.camera);
  writeDefault(vertex, program.vertex_reflection, "u_view_projection", &vp[0][0], 64);
  writeDefault(vertex, program.vertex_reflection, "u_lod", &v.impostor_lod, 4);
  const glm::uvec4 grid = c.impostor.grid();
  writeDefault(vertex, program.vertex_reflection, "u_impostor_grid", &grid[0], 16);
  const glm::vec4 viewer = si::detail::impostorViewer(v.camera);
  writeDefault(vertex, program.vertex_reflection, "u_viewer", &viewer[0], 16);
  writeFragmentDefaults(region.mapped + fragment_at, program.fragment_reflection, light_direction);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, passes.draws[k]);
  uint32_t offsets[kMaxDrawOffsets] = {};
  const uint32_t count =
      drawOffsets(passes.draw_layout.dynamic_bindings, vertex_at, fragment_at, offsets);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, passes.draw_layout.pipeline_layout,
                          0, 1, &v.impostor_sets[1], count, offsets);
  vkCmdDrawIndirect(cmd, v.commands.buffer, kImpostorCommandBytes, 1, 16);
  return Status::ok();
}

}  // namespace si::vk::detail
