// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What a draw sets of the host's rendering: the camera's projection in Vulkan's clip depth, and
// the dynamic state (viewport, scissor, depth test, front face, depth bias) recorded per draw.

#include <vulkan/vulkan.h>

#include <vector>

#include <glm/glm.hpp>

#include "si/crowd/camera.h"
#include "si/vk/renderer.h"
#include "vk/spirv_reflect.h"

namespace si::vk::detail {

/// `camera`'s view-projection with Vulkan's clip depth (0 to w): OpenGL's -w to w mapped, a
/// zero-to-one or reverse-Z projection as it is.
glm::mat4 vulkanViewProjection(const Camera& camera);

/// Records `target`'s dynamic state into `cmd`: the viewport flipped (negative height, so the
/// image is OpenGL's) and the scissor over its extent; its depth test, or the camera
/// convention's (LESS, GREATER under reverse-Z); counter-clockwise front faces (OpenGL's under
/// the flipped viewport), clockwise when the camera's projection mirrors the image; its depth
/// bias, enabled when not zero.
void recordDrawState(VkCommandBuffer cmd, const DrawTarget& target, const Camera& camera);

/// The most dynamic buffers a GPU-driven draw's set offsets (drawOffsets).
inline constexpr uint32_t kMaxDrawOffsets = 8;

/// The dynamic offsets of a draw whose set's dynamic buffers, in binding order, are `bindings`
/// (at most kMaxDrawOffsets; the renderer checks at init): the vertex and fragment stages'
/// defaults at `vertex_at` and `fragment_at`, any other at 0 (a block the programs declare and
/// never read there, such as the instanced path's records in the GPU-driven composed draws).
/// Into `out`; returns their count.
uint32_t drawOffsets(const std::vector<uint32_t>& bindings, VkDeviceSize vertex_at,
                     VkDeviceSize fragment_at, uint32_t out[kMaxDrawOffsets]);

/// Writes the fragment stage's defaults every built-in draw sets into `block` (the stage's default
/// uniform block, reflected as `fragment`): no custom texture layers, the light's direction.
void writeFragmentDefaults(uint8_t* block, const SpirvReflection& fragment,
                           const glm::vec3& light_direction);

}  // namespace si::vk::detail
