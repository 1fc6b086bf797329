// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// What a draw sets of the host's rendering.
#include "vk/draw_state.h"

#include "si_vk/vulkan_profile.h"

namespace si::vk::detail {

namespace {
// The depth test a draw asks for: the given one, or the camera convention's.
VkCompareOp depthCompare(const DrawTarget& target, const Camera& camera) {
  if (target.depth_compare != VK_COMPARE_OP_MAX_ENUM) return target.depth_compare;
  return camera.depth == DepthConvention::kReversedZeroToOne ? VK_COMPARE_OP_GREATER
                                                             : VK_COMPARE_OP_LESS;
}

}  // namespace

glm::mat4 vulkanViewProjection(const Camera& camera) {
  if (camera.depth != DepthConvention::kNegativeOneToOne) return camera.viewProjection();
  glm::mat4 m(1.0f);
  m[2][2] = 0.5f;
  m[3][2] = 0.5f;
  return m * camera.viewProjection();
}

void recordDrawState(VkCommandBuffer cmd, const DrawTarget& target, const Camera& camera) {
  const VkExtent2D extent = target.extent;
  const VkOffset2D at = target.offset;
  const VkViewport viewport{float(at.x),
                            float(at.y) + float(extent.height),
                            float(extent.width),
                            -float(extent.height),
                            0.0f,
                            1.0f};
  const VkRect2D scissor{at, extent};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  vkCmdSetDepthCompareOp(cmd, depthCompare(target, camera));
  vkCmdSetFrontFace(
      cmd, camera.flipsWinding() ? VK_FRONT_FACE_CLOCKWISE : VK_FRONT_FACE_COUNTER_CLOCKWISE);
  const bool bias = target.depth_bias_constant != 0.0f || target.depth_bias_slope != 0.0f;
  vkCmdSetDepthBiasEnable(cmd, bias ? VK_TRUE : VK_FALSE);
  vkCmdSetDepthBias(cmd, target.depth_bias_constant, 0.0f, target.depth_bias_slope);
}

void writeFragmentDefaults(uint8_t* block, const SpirvReflection& fragment,
                           const glm::vec3& light_direction) {
  const uint32_t no_custom_layers = 0;
  writeDefault(block, fragment, "u_custom_layers", &no_custom_layers, 4);
  writeDefault(block, fragment, "u_light_direction", &light_direction, 12);
}

uint32_t drawOffsets(const std::vector<uint32_t>& bindings, VkDeviceSize vertex_at,
                     VkDeviceSize fragment_at, uint32_t out[kMaxDrawOffsets]) {
  uint32_t count = 0;
  for (uint32_t b : bindings) {
    if (count == kMaxDrawOffsets) break;
    out[count++] = b == kVertexDefaultsBinding     ? uint32_t(vertex_at)
                   : b == kFragmentDefaultsBinding ? uint32_t(fragment_at)
                                                   : 0u;
  }
  return count;
}

}  // namespace si::vk::detail
