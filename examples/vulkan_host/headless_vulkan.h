// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// An engine-like Vulkan host (issue "The crowd in a Vulkan engine", item 4), as the vulkan_host
// example, crowd_bench's Vulkan table and the Vulkan render tests use it: its own instance (the
// Khronos validation layer on when installed, every warning and error it reports kept), a
// Vulkan 1.3 device with dynamic rendering (lavapipe on machines without a GPU), a queue,
// colour (RGBA8), motion (RG16F) and depth (D32) targets, and a frame that clears them, lets the
// crowd record into its rendering, reads colour and depth back and times the recording with
// timestamps. No surface: headless. Raw Vulkan: what an engine owns, the library never creates.
#include <vulkan/vulkan.h>

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/status.h"

namespace si::examples {

class HeadlessVulkan {
 public:
  HeadlessVulkan() = default;
  HeadlessVulkan(const HeadlessVulkan&) = delete;
  HeadlessVulkan& operator=(const HeadlessVulkan&) = delete;
  ~HeadlessVulkan();

  /// Creates everything for `width` x `height` targets of `samples` samples (multisampled
  /// targets are resolved at the end of each rendering into single-sampled ones, which are read
  /// back: the colour and motion averaged, the depth of sample 0). kUnsupported when the
  /// machine has no Vulkan 1.3 device with dynamic rendering (install mesa-vulkan-drivers:
  /// lavapipe) or renders no such sample count.
  Status create(uint32_t width, uint32_t height,
                VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT);

  VkPhysicalDevice physicalDevice() const { return physical_; }
  VkDevice device() const { return device_; }
  bool validation() const { return validation_; }  ///< The validation layer is on.
  const std::vector<std::string>& messages() const { return messages_; }
  std::string deviceName() const { return device_name_; }
  VkSampleCountFlagBits samples() const { return samples_; }  ///< Of the attachments.

  /// Records `work` into a command buffer, submits it and waits for it.
  Status submit(const std::function<Status(VkCommandBuffer)>& work);
  /// The motion attachment's format (Frame::motion).
  static constexpr VkFormat kMotionFormat = VK_FORMAT_R16G16_SFLOAT;
  /// How a frame's rendering begins.
  struct Frame {
    glm::vec4 clear_color = glm::vec4(0.0f);
    float clear_depth = 1.0f;  ///< 0 under reverse-Z.
    bool color = true;         ///< A colour attachment; false: depth only (a shadow map).
    bool motion = false;       ///< Colour attachment 1, kMotionFormat, cleared to 0.
    /// Recorded before the rendering begins (the crowd's compute passes), when set.
    std::function<Status(VkCommandBuffer)> before;
    /// Occlusion culling's second phase, when set: after `draw` the rendering ends, the depth
    /// goes to VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL (its writes visible to compute
    /// shaders), `between` is recorded with the depth's view, the depth goes back, and a second
    /// rendering over the same targets (loading what the first left) records `after`.
    std::function<Status(VkCommandBuffer, VkImageView depth)> between;
    std::function<Status(VkCommandBuffer)> after;
  };
  /// What a frame reads back once it is done (each when not null).
  struct Readback {
    std::vector<uint8_t>* rgba = nullptr;      ///< The colour: RGBA8, rows top to bottom.
    std::vector<float>* depth = nullptr;       ///< Window depth, 0-1.
    std::vector<glm::vec2>* motion = nullptr;  ///< The motion attachment (Frame::motion).
    /// GPU time from before Frame::before to after `draw` (or Frame::after), and (with gpu_ms)
    /// of Frame::before alone (to a timestamp once its work is done; the GPU-driven passes).
    double* gpu_ms = nullptr;
    double* before_gpu_ms = nullptr;
  };
  /// One frame: Frame::before recorded, the targets cleared as `frame` says, `draw` recording
  /// inside dynamic rendering over them, then what `out` asks read back. It waits for the frame.
  /// kUnsupported for GPU time on a queue without timestamps; kInvalidArgument for motion without
  /// colour.
  Status render(const Frame& frame, const std::function<Status(VkCommandBuffer)>& draw,
                const Readback& out);

  /// The validation layer's callback.
  void report(const char* message) { messages_.push_back(message); }

 private:
  // One image with its memory and view.
  struct Target {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
  };
  Status createTarget(VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                      VkSampleCountFlagBits samples, Target* out);
  void destroy(Target* t);

  uint32_t width_ = 0, height_ = 0;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkSampleCountFlagBits samples_ = VK_SAMPLE_COUNT_1_BIT;
  // The attachments; multisampled, also their resolved images (read back).
  Target color_, depth_, motion_;
  Target color_resolved_, depth_resolved_, motion_resolved_;
  // Three: before a frame's Frame::before, after its draw, and after Frame::before.
  VkQueryPool timestamps_ = VK_NULL_HANDLE;
  bool timestamps_valid_ = false;
  float timestamp_period_ns_ = 1.0f;
  VkBuffer readback_ = VK_NULL_HANDLE;
  VkDeviceMemory readback_memory_ = VK_NULL_HANDLE;
  bool validation_ = false;
  std::string device_name_;
  std::vector<std::string> messages_;
};

}  // namespace si::examples
