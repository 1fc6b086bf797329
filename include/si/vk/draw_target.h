// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Where a si::vk::Renderer draw lands in the host's rendering and what it writes (DrawTarget,
/// DrawMode; recordDraw, recordGpuDrivenDraw; si/vk/renderer.h), and what it recorded
/// (DrawStats).

#include <cstdint>

#include <vulkan/vulkan.h>

namespace si::vk {

/// What a draw writes.
enum class DrawMode : uint8_t {
  /// Colour (the built-in material) and depth, in a rendering of RendererDesc::color_format and
  /// depth_format (and motion_format as colour attachment 1, when set).
  kShaded = 0,
  /// Depth only (a shadow view, a depth pre-pass), in a rendering with no colour attachment and
  /// a depth attachment of RendererDesc::depth_only_format.
  kDepthOnly,
};

/// Where a draw lands in the host's rendering, and how it tests depth.
struct DrawTarget {
  /// The area drawn: `extent` wide from `offset` (non-negative) in the rendering's
  /// attachments, the viewport and scissor (a shadow atlas's cascade, a split screen's half).
  VkExtent2D extent{0, 0};
  VkOffset2D offset{0, 0};
  DrawMode mode = DrawMode::kShaded;
  /// The depth test. VK_COMPARE_OP_MAX_ENUM (the default) is the camera's convention:
  /// VK_COMPARE_OP_LESS, or VK_COMPARE_OP_GREATER for DepthConvention::kReversedZeroToOne (the
  /// depth cleared to 0). Any other VkCompareOp is used as given (VK_COMPARE_OP_EQUAL after a
  /// depth pre-pass, for one).
  VkCompareOp depth_compare = VK_COMPARE_OP_MAX_ENUM;
  /// Depth bias (shadow maps), as vkCmdSetDepthBias's constant and slope factors; both 0: none.
  float depth_bias_constant = 0.0f;
  float depth_bias_slope = 0.0f;
};

/// What recordDraw() recorded.
struct DrawStats {
  uint32_t draw_calls = 0;
  uint64_t triangles = 0;
  uint64_t instances = 0;
};

}  // namespace si::vk
