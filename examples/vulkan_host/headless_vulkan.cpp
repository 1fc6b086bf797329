// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The engine-like headless Vulkan host: raw Vulkan 1.3, nothing of the library's but its
// public si::Status.
#include "vulkan_host/headless_vulkan.h"

#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <glm/gtc/packing.hpp>

namespace si::examples {

namespace {

// A Vulkan structure of `type`, zeroed.
template <typename T>
T vkStruct(VkStructureType type) {
  T v{};
  v.sType = type;
  return v;
}

Status checkVk(VkResult result, const char* call) {
  if (result == VK_SUCCESS) return Status::ok();
  return {StatusCode::kBackend,
          std::string(call) + " failed: VkResult " + std::to_string(int(result))};
}

// One image layout transition, waiting for `src_access` in `src` before `dst_access` in `dst`.
void transition(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                VkImageLayout to, VkAccessFlags src_access, VkAccessFlags dst_access,
                VkPipelineStageFlags src, VkPipelineStageFlags dst) {
  auto b = vkStruct<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {aspect, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, src, dst, 0, 0, nullptr, 0, nullptr, 1, &b);
}

VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                         VkDebugUtilsMessageTypeFlagsEXT,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data,
                                         void* host) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)
    static_cast<HeadlessVulkan*>(host)->report(data->pMessage);
  return VK_FALSE;
}

uint32_t memoryType(VkPhysicalDevice physical, uint32_t bits, VkMemoryPropertyFlags flags) {
  VkPhysicalDeviceMemoryProperties p{};
  vkGetPhysicalDeviceMemoryProperties(physical, &p);
  for (uint32_t t = 0; t < p.memoryTypeCount; ++t)
    if ((bits & (1u << t)) != 0 && (p.memoryTypes[t].propertyFlags & flags) == flags) return t;
  return UINT32_MAX;
}

}  // namespace

HeadlessVulkan::~HeadlessVulkan() {
  const size_t reported = messages_.size();
  if (device_ != VK_NULL_HANDLE) {
    vkDeviceWaitIdle(device_);
    vkDestroyBuffer(device_, readback_, nullptr);
    vkFreeMemory(device_, readback_memory_, nullptr);
    for (Target* t :
         {&color_, &depth_, &motion_, &color_resolved_, &depth_resolved_, &motion_resolved_})
      destroy(t);
    if (timestamps_ != VK_NULL_HANDLE) vkDestroyQueryPool(device_, timestamps_, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  // The validation layer's object tracker names every object left on the device (a guest that
  // did not destroy what it made): a leak that LeakSanitizer cannot tell from the driver's own
  // caches (tests/lsan.supp). Fatal, so that a test or example that leaks fails.
  if (messages_.size() > reported) {
    for (size_t k = reported; k < messages_.size(); ++k)
      std::fprintf(stderr, "HeadlessVulkan: at vkDestroyDevice: %s\n", messages_[k].c_str());
    std::abort();
  }
  if (messenger_ != VK_NULL_HANDLE) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy != nullptr) destroy(instance_, messenger_, nullptr);
  }
  if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

Status HeadlessVulkan::create(uint32_t width, uint32_t height, VkSampleCountFlagBits samples) {
  width_ = width;
  height_ = height;
  samples_ = samples;
  // The validation layer and its messenger, when installed.
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const VkLayerProperties& l : layers)
    validation_ = validation_ || std::strcmp(l.layerName, "VK_LAYER_KHRONOS_validation") == 0;
  const char* layer = "VK_LAYER_KHRONOS_validation";
  const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  auto app = vkStruct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "SkinnedInstancing headless Vulkan host";
  app.apiVersion = VK_API_VERSION_1_3;
  auto messenger = vkStruct<VkDebugUtilsMessengerCreateInfoEXT>(
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = &onMessage;
  messenger.pUserData = this;
  auto info = vkStruct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  info.pApplicationInfo = &app;
  if (validation_) {
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = &layer;
    info.enabledExtensionCount = 1;
    info.ppEnabledExtensionNames = &extension;
    info.pNext = &messenger;
  }
  Status s = checkVk(vkCreateInstance(&info, nullptr, &instance_), "vkCreateInstance");
  if (!s.isOk()) return {StatusCode::kUnsupported, "no Vulkan instance: " + s.message()};
  // The driver and layer libraries the loader opened stay loaded after the instance is gone,
  // so a leak checker (LeakSanitizer in the sanitized builds) can name what they keep at exit
  // (tests/lsan.supp lists them) rather than an unknown module.
  for (const char* library : {"libvulkan_lvp.so", "libVkLayer_khronos_validation.so"})
    dlopen(library, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
  if (validation_) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (create != nullptr) create(instance_, &messenger, nullptr, &messenger_);
  }
  // A Vulkan 1.3 device with a graphics queue and dynamic rendering.
  vkEnumeratePhysicalDevices(instance_, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance_, &count, devices.data());
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties p{};
    vkGetPhysicalDeviceProperties(d, &p);
    if (p.apiVersion < VK_API_VERSION_1_3) continue;
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &families, nullptr);
    std::vector<VkQueueFamilyProperties> f(families);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &families, f.data());
    for (uint32_t k = 0; k < families && physical_ == VK_NULL_HANDLE; ++k)
      if ((f[k].queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0) {
        physical_ = d;
        queue_family_ = k;
        device_name_ = p.deviceName;
        timestamp_period_ns_ = p.limits.timestampPeriod;
        timestamps_valid_ = f[k].timestampValidBits != 0;
      }
  }
  if (physical_ == VK_NULL_HANDLE)
    return {StatusCode::kUnsupported, "no Vulkan 1.3 device with a graphics queue"};
  const float priority = 1.0f;
  auto queue = vkStruct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queue.queueFamilyIndex = queue_family_;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  auto f13 = vkStruct<VkPhysicalDeviceVulkan13Features>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES);
  f13.dynamicRendering = VK_TRUE;
  f13.synchronization2 = VK_TRUE;
  // What si::vk's GPU-driven path needs, where the device has it (RendererDesc::gpu_driven).
  VkPhysicalDeviceFeatures supported{};
  vkGetPhysicalDeviceFeatures(physical_, &supported);
  auto features = vkStruct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
  features.pNext = &f13;
  features.features.shaderFloat64 = supported.shaderFloat64;
  features.features.multiDrawIndirect = supported.multiDrawIndirect;
  features.features.drawIndirectFirstInstance = supported.drawIndirectFirstInstance;
  auto device = vkStruct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  device.pNext = &features;
  device.queueCreateInfoCount = 1;
  device.pQueueCreateInfos = &queue;
  s = checkVk(vkCreateDevice(physical_, &device, nullptr, &device_), "vkCreateDevice");
  if (!s.isOk()) return s;
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  auto pool = vkStruct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool.queueFamilyIndex = queue_family_;
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  s = checkVk(vkCreateCommandPool(device_, &pool, nullptr, &pool_), "vkCreateCommandPool");
  if (s.isOk() && timestamps_valid_) {
    auto query = vkStruct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
    query.queryType = VK_QUERY_TYPE_TIMESTAMP;
    query.queryCount = 3;
    s = checkVk(vkCreateQueryPool(device_, &query, nullptr, &timestamps_), "vkCreateQueryPool");
  }
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(physical_, &props);
  if (s.isOk() && (props.limits.framebufferColorSampleCounts &
                   props.limits.framebufferDepthSampleCounts & samples) == 0)
    s = {StatusCode::kUnsupported,
         "the device renders no " + std::to_string(int(samples)) + " samples"};
  // The attachments (the depth also read by occlusion culling) and, multisampled, the
  // single-sampled images they resolve into.
  const bool multisampled = samples != VK_SAMPLE_COUNT_1_BIT;
  const VkImageUsageFlags colour =
      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  const VkImageUsageFlags depth =
      VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  if (s.isOk())
    s = createTarget(VK_FORMAT_R8G8B8A8_UNORM, colour, VK_IMAGE_ASPECT_COLOR_BIT, samples, &color_);
  if (s.isOk())
    s = createTarget(kMotionFormat, colour, VK_IMAGE_ASPECT_COLOR_BIT, samples, &motion_);
  if (s.isOk())
    s = createTarget(VK_FORMAT_D32_SFLOAT, depth | VK_IMAGE_USAGE_SAMPLED_BIT,
                     VK_IMAGE_ASPECT_DEPTH_BIT, samples, &depth_);
  if (s.isOk() && multisampled)
    s = createTarget(VK_FORMAT_R8G8B8A8_UNORM, colour, VK_IMAGE_ASPECT_COLOR_BIT,
                     VK_SAMPLE_COUNT_1_BIT, &color_resolved_);
  if (s.isOk() && multisampled)
    s = createTarget(kMotionFormat, colour, VK_IMAGE_ASPECT_COLOR_BIT, VK_SAMPLE_COUNT_1_BIT,
                     &motion_resolved_);
  if (s.isOk() && multisampled)
    s = createTarget(VK_FORMAT_D32_SFLOAT, depth, VK_IMAGE_ASPECT_DEPTH_BIT, VK_SAMPLE_COUNT_1_BIT,
                     &depth_resolved_);
  if (!s.isOk()) return s;
  auto buffer = vkStruct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  buffer.size = VkDeviceSize(width) * height * 12;  // The colour, the depth, the motion.
  buffer.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  s = checkVk(vkCreateBuffer(device_, &buffer, nullptr, &readback_), "vkCreateBuffer");
  if (!s.isOk()) return s;
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(device_, readback_, &req);
  auto alloc = vkStruct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex =
      memoryType(physical_, req.memoryTypeBits,
                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  s = checkVk(vkAllocateMemory(device_, &alloc, nullptr, &readback_memory_), "vkAllocateMemory");
  if (s.isOk())
    s = checkVk(vkBindBufferMemory(device_, readback_, readback_memory_, 0), "vkBindBufferMemory");
  return s;
}

void HeadlessVulkan::destroy(Target* t) {
  vkDestroyImageView(device_, t->view, nullptr);
  vkDestroyImage(device_, t->image, nullptr);
  vkFreeMemory(device_, t->memory, nullptr);
  *t = Target();
}

Status HeadlessVulkan::createTarget(VkFormat format, VkImageUsageFlags usage,
                                    VkImageAspectFlags aspect, VkSampleCountFlagBits samples,
                                    Target* out) {
  VkImage* image = &out->image;
  VkDeviceMemory* memory = &out->memory;
  VkImageView* view = &out->view;
  auto info = vkStruct<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width_, height_, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = samples;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  Status s = checkVk(vkCreateImage(device_, &info, nullptr, image), "vkCreateImage");
  if (!s.isOk()) return s;
  VkMemoryRequirements req{};
  vkGetImageMemoryRequirements(device_, *image, &req);
  auto alloc = vkStruct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex =
      memoryType(physical_, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  s = checkVk(vkAllocateMemory(device_, &alloc, nullptr, memory), "vkAllocateMemory");
  if (s.isOk()) s = checkVk(vkBindImageMemory(device_, *image, *memory, 0), "vkBindImageMemory");
  if (!s.isOk()) return s;
  auto v = vkStruct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
  v.image = *image;
  v.viewType = VK_IMAGE_VIEW_TYPE_2D;
  v.format = format;
  v.subresourceRange = {aspect, 0, 1, 0, 1};
  return checkVk(vkCreateImageView(device_, &v, nullptr, view), "vkCreateImageView");
}

Status HeadlessVulkan::submit(const std::function<Status(VkCommandBuffer)>& work) {
  auto alloc =
      vkStruct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  alloc.commandPool = pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  Status s = checkVk(vkAllocateCommandBuffers(device_, &alloc, &cmd), "vkAllocateCommandBuffers");
  if (!s.isOk()) return s;
  auto begin = vkStruct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  s = checkVk(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  if (s.isOk()) s = work(cmd);
  const Status ended = checkVk(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  if (s.isOk()) s = ended;
  if (s.isOk()) {
    auto submit = vkStruct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    s = checkVk(vkQueueSubmit(queue_, 1, &submit, VK_NULL_HANDLE), "vkQueueSubmit");
    if (s.isOk()) s = checkVk(vkQueueWaitIdle(queue_), "vkQueueWaitIdle");
  }
  vkFreeCommandBuffers(device_, pool_, 1, &cmd);
  return s;
}

Status HeadlessVulkan::render(const Frame& frame,
                              const std::function<Status(VkCommandBuffer)>& draw,
                              const Readback& out) {
  if (out.gpu_ms != nullptr && timestamps_ == VK_NULL_HANDLE)
    return {StatusCode::kUnsupported, "the queue writes no timestamps"};
  if (frame.motion && !frame.color)
    return {StatusCode::kInvalidArgument, "motion vectors without a colour attachment"};
  // The readback buffer: the colour, the depth, the motion (4 bytes a pixel each).
  const VkDeviceSize plane = VkDeviceSize(width_) * height_ * 4;
  const Status s = submit([&](VkCommandBuffer cmd) {
    constexpr VkAccessFlags kDepthAccess =
        VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    constexpr VkPipelineStageFlags kDepthStages =
        VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    // Multisampled, each attachment resolves at the end of each rendering into its resolved
    // image (written as a colour attachment is, depth included), which is read back.
    const bool multisampled = samples_ != VK_SAMPLE_COUNT_1_BIT;
    constexpr VkPipelineStageFlags kResolveStages =
        VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | kDepthStages;
    constexpr VkAccessFlags kResolveAccess =
        VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    // The colour attachments this frame has: the colour, and the motion when asked.
    struct Attachment {
      const Target* target;
      const Target* read;  // The image read back: the target, or the one it resolves into.
      glm::vec4 clear;
      std::vector<uint8_t>* rgba;      // Read back as bytes (the colour) ...
      std::vector<glm::vec2>* motion;  // ... or as two half floats (the motion).
      VkDeviceSize at;
    };
    std::vector<Attachment> attachments;
    if (frame.color)
      attachments.push_back({&color_, multisampled ? &color_resolved_ : &color_, frame.clear_color,
                             out.rgba, nullptr, 0});
    if (frame.motion)
      attachments.push_back({&motion_, multisampled ? &motion_resolved_ : &motion_, glm::vec4(0.0f),
                             nullptr, out.motion, 2 * plane});
    std::vector<VkRenderingAttachmentInfo> colors;
    for (const Attachment& a : attachments) {
      for (const Target* t : {a.target, a.read})
        if (t == a.target || multisampled)  // The resolved image too, when there is one.
          transition(cmd, t->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, 0,
                     VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                     VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
      auto info = vkStruct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
      info.imageView = a.target->view;
      info.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
      info.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
      info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
      info.clearValue.color = {{a.clear.r, a.clear.g, a.clear.b, a.clear.a}};
      if (multisampled) {
        info.resolveMode = VK_RESOLVE_MODE_AVERAGE_BIT;
        info.resolveImageView = a.read->view;
        info.resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
      }
      colors.push_back(info);
    }
    const Target& depth_read = multisampled ? depth_resolved_ : depth_;
    for (const Target* t : {&depth_, &depth_resolved_})
      if (t == &depth_ || multisampled)
        transition(cmd, t->image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                   VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, 0, kDepthAccess | kResolveAccess,
                   VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, kResolveStages);
    auto depth = vkStruct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
    depth.imageView = depth_.view;
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    // Kept for the read back, and for the second phase's compute read and load.
    depth.storeOp = out.depth != nullptr || frame.between ? VK_ATTACHMENT_STORE_OP_STORE
                                                          : VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depth.clearValue.depthStencil = {frame.clear_depth, 0};
    if (multisampled) {
      depth.resolveMode = VK_RESOLVE_MODE_SAMPLE_ZERO_BIT;
      depth.resolveImageView = depth_resolved_.view;
      depth.resolveImageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    }
    auto rendering = vkStruct<VkRenderingInfo>(VK_STRUCTURE_TYPE_RENDERING_INFO);
    rendering.renderArea = {{0, 0}, {width_, height_}};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = uint32_t(colors.size());
    rendering.pColorAttachments = colors.empty() ? nullptr : colors.data();
    rendering.pDepthAttachment = &depth;
    if (out.gpu_ms != nullptr) {
      vkCmdResetQueryPool(cmd, timestamps_, 0, 3);
      vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps_, 0);
    }
    const Status prepared = frame.before ? frame.before(cmd) : Status::ok();
    // Once what Frame::before recorded is done: its share of the GPU time.
    if (out.gpu_ms != nullptr)
      vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps_, 2);
    vkCmdBeginRendering(cmd, &rendering);
    Status drawn = prepared.isOk() ? draw(cmd) : prepared;
    if (frame.between) {
      // The second phase: the depth read by compute shaders, then a rendering that loads it.
      vkCmdEndRendering(cmd);
      transition(cmd, depth_.image, VK_IMAGE_ASPECT_DEPTH_BIT,
                 VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
                 kDepthStages, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
      if (drawn.isOk()) drawn = frame.between(cmd, depth_.view);
      transition(cmd, depth_.image, VK_IMAGE_ASPECT_DEPTH_BIT,
                 VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                 VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, 0, kDepthAccess,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, kDepthStages);
      for (const Attachment& a : attachments)  // The first rendering's colour, loaded.
        transition(cmd, a.target->image, VK_IMAGE_ASPECT_COLOR_BIT,
                   VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                   VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                   VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
      for (VkRenderingAttachmentInfo& c : colors) c.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
      depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
      vkCmdBeginRendering(cmd, &rendering);
      if (drawn.isOk() && frame.after) drawn = frame.after(cmd);
    }
    if (out.gpu_ms != nullptr)
      vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps_, 1);
    vkCmdEndRendering(cmd);
    for (const Attachment& a : attachments) {
      if (a.rgba == nullptr && a.motion == nullptr) continue;
      transition(cmd, a.read->image, VK_IMAGE_ASPECT_COLOR_BIT,
                 VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                 VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
      VkBufferImageCopy copy{};
      copy.bufferOffset = a.at;
      copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      copy.imageExtent = {width_, height_, 1};
      vkCmdCopyImageToBuffer(cmd, a.read->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_, 1,
                             &copy);
    }
    if (out.depth != nullptr) {
      transition(cmd, depth_read.image, VK_IMAGE_ASPECT_DEPTH_BIT,
                 VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | kResolveAccess,
                 VK_ACCESS_TRANSFER_READ_BIT, kResolveStages, VK_PIPELINE_STAGE_TRANSFER_BIT);
      VkBufferImageCopy copy{};
      copy.bufferOffset = plane;
      copy.imageSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1};
      copy.imageExtent = {width_, height_, 1};
      vkCmdCopyImageToBuffer(cmd, depth_read.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_,
                             1, &copy);
    }
    return drawn;
  });
  if (!s.isOk()) return s;
  void* mapped = nullptr;
  const Status m =
      checkVk(vkMapMemory(device_, readback_memory_, 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
  if (!m.isOk()) return m;
  const uint8_t* bytes = static_cast<const uint8_t*>(mapped);
  const size_t pixels = size_t(width_) * height_;
  if (frame.color && out.rgba != nullptr) out.rgba->assign(bytes, bytes + pixels * 4);
  if (out.depth != nullptr) {
    out.depth->resize(pixels);
    std::memcpy(out.depth->data(), bytes + plane, pixels * 4);
  }
  if (frame.motion && out.motion != nullptr) {
    out.motion->resize(pixels);
    for (size_t i = 0; i < pixels; ++i) {
      uint32_t halves = 0;
      std::memcpy(&halves, bytes + 2 * plane + i * 4, 4);
      (*out.motion)[i] = glm::unpackHalf2x16(halves);
    }
  }
  vkUnmapMemory(device_, readback_memory_);
  if (out.gpu_ms != nullptr) {
    uint64_t stamps[3] = {};
    const Status read = checkVk(vkGetQueryPoolResults(device_, timestamps_, 0, 3, sizeof(stamps),
                                                      stamps, 8, VK_QUERY_RESULT_64_BIT),
                                "vkGetQueryPoolResults");
    if (!read.isOk()) return read;
    *out.gpu_ms = double(stamps[1] - stamps[0]) * timestamp_period_ns_ * 1e-6;
    if (out.before_gpu_ms != nullptr)
      *out.before_gpu_ms = double(stamps[2] - stamps[0]) * timestamp_period_ns_ * 1e-6;
  }
  return Status::ok();
}

}  // namespace si::examples
