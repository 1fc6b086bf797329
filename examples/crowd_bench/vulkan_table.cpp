// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/vulkan_table.h"

#include <algorithm>
#include <cstdlib>

#include "crowd_bench/bench_character.h"
#include "crowd_bench/gpu_passes_table.h"

#if SI_BENCH_VULKAN
#include "si/vk/renderer.h"
#include "vulkan_host/headless_vulkan.h"
#endif

namespace si::bench {

#if SI_BENCH_VULKAN
namespace {

// Share of pixels whose channels differ by more than 8 levels (the golden tolerance's).
double differingShare(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  if (a.size() != b.size() || a.empty()) return 1.0;
  size_t apart = 0;
  for (size_t i = 0; i + 3 < a.size(); i += 4) {
    int most = 0;
    for (int c = 0; c < 3; ++c) most = std::max(most, std::abs(int(a[i + c]) - int(b[i + c])));
    apart += most > 8;
  }
  return double(apart) / double(a.size() / 4);
}

// Both APIs draw `count` characters of `scene` on `path` ("instanced": drawCrowd and
// recordDraw of the CPU's selection; "gpu-culled": drawCrowdGpuCulled with vertex-shader
// skinning and recordGpuDrivenPasses/recordGpuDrivenDraw, the selection the GPU's; with
// "-occlusion" both phases of occlusion culling, Vulkan's second recorded between two
// renderings) for setup.frames frames: rows[0] GL's, rows[1] Vulkan's; `apart` the share of the
// last frames' pixels that differ; `vk_before_ms` the median GPU time of what Vulkan recorded
// before the host's rendering (the GPU-driven passes; occlusion culling's second phase goes with
// the draws). With RendererDesc::measure_gpu_passes GL's row gets its pass times.
Status runBoth(Setup& setup, Renderer& gl, examples::HeadlessVulkan& host,
               const BakedPalette& palette, const std::string& scene, uint32_t count,
               const std::string& path, const LodChoice& lod, Row rows[2], double* apart,
               double* vk_before_ms) {
  // gpu-culled skins in the vertex stage; gpu-driven pre-skins into the ring first, on both.
  const bool occlusion = path.size() > 10 && path.compare(path.size() - 10, 10, "-occlusion") == 0;
  const std::string base = occlusion ? path.substr(0, path.size() - 10) : path;
  const bool gpu_driven = base == "gpu-culled" || base == "gpu-driven";
  const std::vector<glm::dvec3> places = scenePositions(scene, count);
  CrowdManager crowd;
  Status s = makeCrowd(setup, palette, places, lod, &crowd);
  if (!s.isOk()) return s;
  // A ring region that holds every record of the frame (each instance's worn parts).
  vk::Renderer vkr;
  vk::RendererDesc vd;
  vd.physical_device = host.physicalDevice();
  vd.device = host.device();
  vd.frames_in_flight = 1;  // The host waits for each frame.
  vd.gpu_driven = gpu_driven;
  if (base == "gpu-culled") vd.gpu_driven_ring_bytes = 0;
  vd.ring_bytes_per_frame =
      uint64_t(count) * crowd.desc().sub_mesh_count * 80 + (uint64_t(4) << 20);
  s = vkr.init(vd);
  vk::CharacterId id;
  if (s.isOk()) s = vkr.addCharacter(setup.character, palette, &id);
  // --impostor: an atlas of si::gl's cells, size and capture (captured with the uploads).
  if (s.isOk() && setup.impostor) s = vkr.buildImpostor(id, setup.impostor_desc);
  if (s.isOk()) s = host.submit([&](VkCommandBuffer cmd) { return vkr.recordUploads(cmd); });
  if (!s.isOk()) return {s.code(), "si::vk: " + s.message()};
  vkr.uploadsComplete();
  InstanceBatcher gl_batcher, vk_batcher;
  s = gl_batcher.init(gl.batchLimits());
  if (s.isOk()) s = vk_batcher.init(vkr.batchLimits());
  std::vector<double> update, submit[2], gpu[2], before;
  PassCollector gl_passes(gl);
  uint64_t visible[2] = {};  // GPU-driven: each API's count.
  std::vector<uint8_t> images[2];
  const uint32_t warmup = kWarmupFrames, n = setup.frames;
  for (uint32_t f = 0; f < warmup + n && s.isOk(); ++f) {
    const Camera cam = cameraAt(setup, scene, places, f < warmup ? 0 : f - warmup, n);
    const auto t0 = Clock::now();
    s = stepCrowd(crowd, path, cam, 1.0 / 60.0);
    const double update_ms = msSince(t0);
    const bool last = f + 1 == warmup + n;
    DrawStats gl_stats;
    if (s.isOk()) s = drawPath(gl, crowd, gl_batcher, path, cam, &gl_stats);
    if (s.isOk() && last) s = setup.context->readPixels(&images[0]);
    vk::DrawStats vk_stats;
    double vk_ms = 0.0, vk_before = 0.0, vk_submit_ms = 0.0;
    if (s.isOk()) {
      examples::HeadlessVulkan::Frame frame;
      frame.clear_color = kClearColor;
      frame.before = [&](VkCommandBuffer cmd) {
        const auto t1 = Clock::now();
        Status begun = vkr.beginFrame(0);
        if (begun.isOk() && gpu_driven)
          begun = vkr.recordGpuDrivenPasses(
              cmd, id, crowd.view(), cam, nullptr,
              occlusion ? vk::GpuCulling::kOcclusion : vk::GpuCulling::kFrustum);
        vk_submit_ms = msSince(t1);
        return begun;
      };
      const vk::DrawTarget target{{setup.width, setup.height}};
      uint32_t draw_calls = 0;
      const auto draw = [&](VkCommandBuffer cmd) {
        const auto t1 = Clock::now();
        const Status drawn =
            gpu_driven ? vkr.recordGpuDrivenDraw(cmd, target, id, crowd.view(), &vk_stats)
                       : vkr.recordDraw(cmd, target, id, crowd.view(), vk_batcher, cam, &vk_stats);
        draw_calls += vk_stats.draw_calls;
        vk_submit_ms += msSince(t1);
        return drawn;
      };
      if (occlusion) {  // The second phase between the first's rendering and its own.
        frame.between = [&](VkCommandBuffer cmd, VkImageView depth) {
          const auto t1 = Clock::now();
          vk::DepthSource source;
          source.view = depth;
          source.extent = target.extent;
          const Status second = vkr.recordGpuDrivenOcclusion(cmd, id, crowd.view(), source);
          vk_submit_ms += msSince(t1);
          return second;
        };
        frame.after = draw;
      }
      s = host.render(frame, draw,
                      {last ? &images[1] : nullptr, nullptr, nullptr, &vk_ms, &vk_before});
      vk_stats.draw_calls = draw_calls;
    }
    if (!s.isOk() || f < warmup) continue;
    gl_passes.add(gl_stats.gpu_pass_ticket, f);
    before.push_back(vk_before);
    update.push_back(update_ms);
    submit[0].push_back(gl_stats.cpu_submit_ms);
    gpu[0].push_back(gl_stats.gpu_ms);
    submit[1].push_back(vk_submit_ms);
    gpu[1].push_back(vk_ms);
    rows[0].draws = gl_stats.draw_calls;
    visible[0] = gl_stats.gpu_visible;
    rows[0].triangles = double(gl_stats.triangles);
    rows[1].draws = vk_stats.draw_calls;
    rows[1].triangles = double(vk_stats.triangles);
    if (gpu_driven) {  // The GPU counted what it drew (the host has waited for the frame).
      vk::GpuDrivenCounts counts;
      s = vkr.readGpuDrivenCounts(id, crowd.view(), &counts);
      visible[1] = counts.visible;
      rows[1].triangles = double(counts.triangles);
    }
  }
  vkr.shutdown();
  gl_passes.finish(&rows[0]);
  *vk_before_ms = median(before);
  for (int k = 0; k < 2; ++k) {
    rows[k].scene = scene;
    rows[k].path = path;
    rows[k].lod = k == 0 ? "GL" : "Vulkan";
    rows[k].instances = count;
    rows[k].visible = gpu_driven ? visible[k] : crowd.view().stats().visible;
    rows[k].update_ms = median(update);
    rows[k].submit_ms = median(submit[k]);
    rows[k].gpu_ms = median(gpu[k]);
    rows[k].covered_pixels = coveredPixels(images[k]);
  }
  *apart = differingShare(images[0], images[1]);
  return s;
}

}  // namespace
#endif

Status vulkanTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                   const std::vector<std::string>& scenes, const std::vector<uint32_t>& sizes,
                   const std::vector<std::string>& paths, const LodChoice& lod, std::FILE* csv) {
#if SI_BENCH_VULKAN
  examples::HeadlessVulkan host;
  Status s = host.create(setup.width, setup.height);
  if (!s.isOk()) return {StatusCode::kUnsupported, "no Vulkan device: " + s.message()};
  Renderer gl;
  RendererDesc rd = desc;
  rd.skinning_path = SkinningPath::kVertexShader;
  s = initRenderer(setup, palette, rd, &gl);
  if (!s.isOk()) return s;
  for (const std::string& scene : scenes) {
    std::printf(
        "\nVulkan (%s, %s LODs): si::gl and si::vk (%s, validation %s) drawing the same crowd "
        "and camera each frame, on the instanced path (drawCrowd, recordDraw; vertex-shader "
        "skinning) and the GPU-driven one (drawCrowdGpuCulled, recordGpuDrivenPasses and "
        "recordGpuDrivenDraw; gpu-culled skinning in the vertex stage, gpu-driven pre-skinning "
        "in compute; -occlusion: two-phase occlusion culling, recordGpuDrivenOcclusion between "
        "two renderings); GPU x is Vulkan's GPU time over GL's\n",
        scene.c_str(), lod.name().c_str(), host.deviceName().c_str(),
        host.validation() ? "on" : "not installed");
    printSideBySideHeader("API");
    std::printf(" %12s %12s\n", "covered px", "apart");
    for (const std::string& path : paths) {
      if (path != "instanced" && path != "gpu-culled" && path != "gpu-driven" &&
          path != "gpu-culled-occlusion" && path != "gpu-driven-occlusion") {
        std::printf(
            "  %s: not on the Vulkan back-end yet (instanced, gpu-culled and gpu-driven, with "
            "and without occlusion, are)\n",
            path.c_str());
        continue;
      }
      for (uint32_t count : sizes) {
        Row rows[2];
        double apart = 1.0, vk_before_ms = 0.0;
        s = runBoth(setup, gl, host, palette, scene, count, path, lod, rows, &apart, &vk_before_ms);
        if (!s.isOk()) return s;
        for (const Row& r : rows) {
          printSideBySideRow(r, rows[0], "vulkan", csv);
          std::printf(" %12llu %11.4f%%\n", static_cast<unsigned long long>(r.covered_pixels),
                      &r == &rows[0] ? 0.0 : 100.0 * apart);
        }
        // --gpu-passes: where each API's GPU time goes, the compute passes and the draws.
        if (rows[0].pass_ms.size() == kGpuPassCount) {
          double gl_draws = 0.0, gl_passes = 0.0;
          for (uint32_t p = 0; p < kGpuPassCount; ++p)
            (p == uint32_t(GpuPass::kDraw) || p == uint32_t(GpuPass::kImpostors) ? gl_draws
                                                                                 : gl_passes) +=
                rows[0].pass_ms[p];
          std::printf(
              "    GPU ms: GL passes %.3f (cull %.3f, commands %.3f, scatter %.3f, skin %.3f), "
              "draws %.3f (meshes %.3f, impostors %.3f); Vulkan before the rendering %.3f, the "
              "rest %.3f%s\n",
              gl_passes, rows[0].pass_ms[uint32_t(GpuPass::kCull)],
              rows[0].pass_ms[uint32_t(GpuPass::kCommands)],
              rows[0].pass_ms[uint32_t(GpuPass::kScatter)],
              rows[0].pass_ms[uint32_t(GpuPass::kSkin)], gl_draws,
              rows[0].pass_ms[uint32_t(GpuPass::kDraw)],
              rows[0].pass_ms[uint32_t(GpuPass::kImpostors)], vk_before_ms,
              rows[1].gpu_ms - vk_before_ms,
              path.find("-occlusion") != std::string::npos
                  ? " (the rest: Vulkan's second phase and draws)"
                  : "");
        }
      }
    }
  }
  gl.shutdown();
  for (const std::string& m : host.messages()) std::printf("  validation: %s\n", m.c_str());
  if (!host.messages().empty())
    return {StatusCode::kBackend, "the validation layer reported the messages above"};
  return Status::ok();
#else
  (void)setup, (void)palette, (void)desc, (void)scenes, (void)sizes, (void)paths, (void)lod,
      (void)csv;
  return {StatusCode::kUnsupported, "crowd_bench was built without si::vk (SI_WITH_VULKAN=OFF)"};
#endif
}

}  // namespace si::bench
