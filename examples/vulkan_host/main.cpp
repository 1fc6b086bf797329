// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// vulkan_host: the crowd in a Vulkan engine's frame (issue "The crowd in a Vulkan engine", item
// 4). The host (headless_vulkan.h: raw Vulkan 1.3, no surface) owns the instance, device, queue,
// render targets and pacing; si::vk::Renderer creates its pipelines, buffers and images on the
// host's device and records into the host's command buffers: the character's uploads once, then
// each frame a shadow view depth-only (in a rendering of depth alone, as a shadow map's) and the
// main view shaded, both inside the host's dynamic rendering. The crowd advances and each view
// selects on the CPU (si::CrowdManager, si::CrowdView); with --gpu-driven each view's selection
// is computed on the GPU instead (recordGpuDrivenPasses, recorded before the host's renderings,
// then recordGpuDrivenDraw inside them) and the crowd only advances its clock; with --occlusion
// the main view is also culled against the host's depth in two phases (GpuCulling::kOcclusion,
// then recordGpuDrivenOcclusion between two renderings of the main view). Prints the GPU
// time of each view (the host's timestamps; the passes counted with the shadow view), writes the
// last frame as a PNG, and exits 1 when the validation layer (on when installed) reported
// anything.
// Usage: vulkan_host [--size WxH] [--instances N] [--frames N] [--reverse-z] [--gpu-driven]
//                    [--occlusion] [--samples 1|2|4|8] [--out FILE.png]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "common/field_crowd.h"
#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/crowd_view.h"
#include "si/crowd/instance_batcher.h"
#include "si/headless/headless_context.h"
#include "si/vk/renderer.h"
#include "vulkan_host/headless_vulkan.h"

namespace {

struct Options {
  uint32_t width = 640, height = 360, instances = 2000, frames = 30;
  bool reverse_z = false;
  bool gpu_driven = false;
  bool occlusion = false;  // The main view's occlusion culling (GPU-driven).
  uint32_t samples = 1;    // Of the host's attachments (multisampling: 2, 4, 8).
  std::string out = "vulkan_host.png";
};

int fail(const std::string& what, const si::Status& s = si::Status::ok()) {
  std::fprintf(stderr, "vulkan_host: %s%s%s\n", what.c_str(), s.isOk() ? "" : ": ",
               s.isOk() ? "" : s.toString().c_str());
  return 1;
}

bool parse(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--size" && has) {
      if (std::sscanf(argv[++i], "%ux%u", &o->width, &o->height) != 2 || o->width == 0 ||
          o->height == 0 || o->width > 8192 || o->height > 8192)
        return false;
    } else if (a == "--instances" && has) {
      o->instances = uint32_t(std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--frames" && has) {
      o->frames = uint32_t(std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--reverse-z") {
      o->reverse_z = true;
    } else if (a == "--gpu-driven") {
      o->gpu_driven = true;
    } else if (a == "--occlusion") {
      o->gpu_driven = o->occlusion = true;
    } else if (a == "--samples" && has) {
      o->samples = uint32_t(std::strtoul(argv[++i], nullptr, 10));
      if (o->samples != 1 && o->samples != 2 && o->samples != 4 && o->samples != 8) return false;
    } else if (a == "--out" && has) {
      o->out = argv[++i];
    } else {
      return false;
    }
  }
  return o->instances > 0 && o->frames > 0;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, &o)) {
    std::fprintf(stderr,
                 "usage: vulkan_host [--size WxH] [--instances N] [--frames N] [--reverse-z] "
                 "[--gpu-driven] [--occlusion] [--samples 1|2|4|8] [--out FILE.png]\n");
    return 1;
  }
  // The host's own Vulkan: instance, device, queue and targets.
  si::examples::HeadlessVulkan host;
  si::Status s = host.create(o.width, o.height, VkSampleCountFlagBits(o.samples));
  if (!s.isOk()) return fail("the host's Vulkan device", s);
  std::printf("vulkan_host: %s, validation %s\n", host.deviceName().c_str(),
              host.validation() ? "on" : "not installed");

  // The embedded character, baked; the renderer on the host's device.
  si::Character character;
  s = si::makeDefaultCharacter({}, &character);
  si::BakedPalette palette;
  if (s.isOk()) s = si::bakePalette(character, {}, &palette, nullptr);
  if (!s.isOk()) return fail("the character", s);
  si::vk::Renderer renderer;
  si::vk::RendererDesc rd;
  rd.physical_device = host.physicalDevice();
  rd.device = host.device();
  rd.color_format = VK_FORMAT_R8G8B8A8_UNORM;
  rd.depth_format = VK_FORMAT_D32_SFLOAT;
  // A frame's records: both views' (80 bytes per worn sub-mesh of each instance drawn), with
  // room for the batches' alignment and default blocks.
  rd.ring_bytes_per_frame =
      2 * uint64_t(o.instances) * character.mesh.sub_meshes.size() * 80 + (uint64_t(4) << 20);
  // The GPU-driven path: the host's device has shaderFloat64, multiDrawIndirect and
  // drawIndirectFirstInstance enabled (headless_vulkan.cpp). Each view keeps a ring of
  // pre-skinned vertices: 64 MiB each here.
  rd.gpu_driven = o.gpu_driven;
  rd.gpu_driven_ring_bytes = uint64_t(64) << 20;
  // The host's attachments' samples: the main view's and the shadow view's (one host's targets).
  rd.samples = rd.depth_only_samples = VkSampleCountFlagBits(o.samples);
  s = renderer.init(rd);
  si::vk::CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(character, palette, &id);
  // Its uploads, recorded into a command buffer of the host's and submitted by the host.
  if (s.isOk()) s = host.submit([&](VkCommandBuffer cmd) { return renderer.recordUploads(cmd); });
  if (!s.isOk()) return fail("the renderer", s);
  renderer.uploadsComplete();

  si::CrowdManager crowd;
  si::CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(character.mesh.maxLodCount());
  float half_side = 0.0f;
  s = crowd.init(cd);
  if (s.isOk()) s = si::examples::populateField(o.instances, palette, &crowd, &half_side);
  // The shadow view: its own selection (two LODs coarser), from an orthographic sun camera.
  si::CrowdView shadow_view;
  si::CrowdViewDesc shadow_desc;
  shadow_desc.lod_bias = 2;
  shadow_desc.max_distance_radii = -1.0f;
  if (s.isOk()) s = shadow_view.init(crowd, shadow_desc);
  si::InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  if (!s.isOk()) return fail("the crowd", s);
  const float r = half_side * 1.5f;
  const glm::dvec3 sun_at(-0.4 * 3.0 * half_side, 3.0 * half_side, -0.3 * 3.0 * half_side);
  const glm::dmat4 sun_view = glm::lookAt(sun_at, glm::dvec3(0.0), glm::dvec3(0, 1, 0));
  const si::Camera sun =
      si::Camera::fromMatrices(sun_view, glm::orthoRH_NO(-r, r, -r, r, 0.1f, 8.0f * half_side),
                               si::DepthConvention::kNegativeOneToOne, float(o.height));

  std::vector<double> shadow_ms, main_ms;
  std::vector<uint8_t> rgba;
  uint64_t shadow_texels = 0;
  for (uint32_t f = 0; f < o.frames; ++f) {
    // The camera orbits the field; the crowd advances and each view selects.
    const double angle = 0.02 * f;
    const glm::dvec3 eye(std::sin(angle) * 1.1 * half_side, 0.35 * half_side,
                         std::cos(angle) * 1.1 * half_side);
    const float aspect = float(o.width) / float(o.height);
    si::Camera camera = o.reverse_z ? si::Camera::lookAtReverseZ(eye, glm::dvec3(0.0), {0, 1, 0},
                                                                 0.8f, aspect, 0.3f)
                                    : si::Camera::lookAt(eye, glm::dvec3(0.0), {0, 1, 0}, 0.8f,
                                                         aspect, 0.3f, 4.0f * half_side);
    camera.viewport_height_pixels = float(o.height);
    if (o.gpu_driven) {
      s = crowd.advance(1.0 / 60.0);  // The views select on the GPU.
    } else {
      s = crowd.update(1.0 / 60.0, camera);
      if (s.isOk()) s = shadow_view.select(sun);
    }
    if (!s.isOk()) return fail("the crowd's frame", s);
    const uint32_t slot = f % rd.frames_in_flight;
    // The shadow map: a rendering of depth only.
    si::vk::DrawTarget shadow_target{{o.width, o.height}};
    shadow_target.mode = si::vk::DrawMode::kDepthOnly;
    shadow_target.depth_bias_constant = 1.0f;
    shadow_target.depth_bias_slope = 1.5f;
    si::examples::HeadlessVulkan::Frame shadow_frame;
    shadow_frame.color = false;
    // Before the frame's renderings: the frame slot begins and, GPU-driven, both views' passes.
    shadow_frame.before = [&](VkCommandBuffer cmd) {
      si::Status begun = renderer.beginFrame(slot);
      if (begun.isOk() && o.gpu_driven)
        begun = renderer.recordGpuDrivenPasses(cmd, id, shadow_view, sun);
      if (begun.isOk() && o.gpu_driven)
        begun = renderer.recordGpuDrivenPasses(
            cmd, id, crowd.view(), camera, nullptr,
            o.occlusion ? si::vk::GpuCulling::kOcclusion : si::vk::GpuCulling::kFrustum);
      return begun;
    };
    std::vector<float> depth;
    double ms = 0.0;
    s = host.render(shadow_frame,
                    [&](VkCommandBuffer cmd) {
                      return o.gpu_driven
                                 ? renderer.recordGpuDrivenDraw(cmd, shadow_target, id, shadow_view)
                                 : renderer.recordDraw(cmd, shadow_target, id, shadow_view, batcher,
                                                       sun);
                    },
                    {nullptr, f + 1 == o.frames ? &depth : nullptr, nullptr, &ms});
    if (!s.isOk()) return fail("the shadow view", s);
    shadow_ms.push_back(ms);
    shadow_texels = 0;
    for (float d : depth) shadow_texels += d < 1.0f;
    // The main view, shaded, into the host's colour and depth.
    si::examples::HeadlessVulkan::Frame main_frame;
    main_frame.clear_color = glm::vec4(0.55f, 0.6f, 0.55f, 1.0f);
    main_frame.clear_depth = o.reverse_z ? 0.0f : 1.0f;
    si::vk::DrawStats stats;
    const si::vk::DrawTarget target{{o.width, o.height}};
    const auto draw_main = [&](VkCommandBuffer cmd) {
      // The shadow view's records stay in the slot's region: the main view's follow them.
      si::vk::DrawStats drawn;
      const si::Status d =
          o.gpu_driven
              ? renderer.recordGpuDrivenDraw(cmd, target, id, crowd.view(), &drawn)
              : renderer.recordDraw(cmd, target, id, crowd.view(), batcher, camera, &drawn);
      stats.draw_calls += drawn.draw_calls;
      stats.triangles += drawn.triangles;
      return d;
    };
    if (o.occlusion) {
      // The first phase drawn, the rendering ends: the host's depth (read-only for compute
      // shaders) reduced and the second phase recorded; its draw in a rendering that loads.
      main_frame.between = [&](VkCommandBuffer cmd, VkImageView depth_view) {
        si::vk::DepthSource source;
        source.view = depth_view;
        source.extent = target.extent;
        source.samples = host.samples();
        return renderer.recordGpuDrivenOcclusion(cmd, id, crowd.view(), source);
      };
      main_frame.after = draw_main;
    }
    s = host.render(main_frame, draw_main,
                    {f + 1 == o.frames ? &rgba : nullptr, nullptr, nullptr, &ms});
    if (!s.isOk()) return fail("the main view", s);
    main_ms.push_back(ms);
    if (f + 1 == o.frames && o.gpu_driven) {
      si::vk::GpuDrivenCounts counts;  // The host has waited for the frame.
      s = renderer.readGpuDrivenCounts(id, crowd.view(), &counts);
      if (!s.isOk()) return fail("the main view's counts", s);
      std::printf(
          "vulkan_host: last frame GPU-driven%s, %u indirect draws, %u visible, %llu "
          "triangles\n",
          o.occlusion ? " with occlusion culling" : "", stats.draw_calls, counts.visible,
          static_cast<unsigned long long>(counts.triangles));
    } else if (f + 1 == o.frames)
      std::printf("vulkan_host: last frame %u visible, %u draws, %llu triangles\n",
                  crowd.view().stats().visible, stats.draw_calls,
                  static_cast<unsigned long long>(stats.triangles));
  }
  uint64_t covered = 0;
  for (size_t i = 0; i + 3 < rgba.size(); i += 4)
    covered += rgba[i] != 140 || rgba[i + 1] != 153 || rgba[i + 2] != 140;
  std::printf(
      "vulkan_host: %u instances, %u frames at %ux%u, %u sample%s%s: GPU median %.3f ms shadow "
      "view (depth only), %.3f ms main view; covered pixels %llu, shadow texels %llu\n",
      o.instances, o.frames, o.width, o.height, o.samples, o.samples == 1 ? "" : "s",
      o.occlusion ? (o.reverse_z ? ", GPU-driven, occlusion, reverse-Z" : ", GPU-driven, occlusion")
      : o.gpu_driven ? (o.reverse_z ? ", GPU-driven, reverse-Z" : ", GPU-driven")
      : o.reverse_z  ? ", reverse-Z"
                     : "",
      median(shadow_ms), median(main_ms), static_cast<unsigned long long>(covered),
      static_cast<unsigned long long>(shadow_texels));
  s = si::writePng(o.out, o.width, o.height, rgba);
  if (!s.isOk()) return fail("writing " + o.out, s);
  renderer.shutdown();
  for (const std::string& m : host.messages()) std::fprintf(stderr, "validation: %s\n", m.c_str());
  if (!host.messages().empty()) return fail("the validation layer reported the messages above");
  return covered > 0 && shadow_texels > 0 ? 0 : fail("nothing was drawn");
}
