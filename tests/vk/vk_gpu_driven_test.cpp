// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The Vulkan back-end's GPU-driven path (issue "The crowd in a Vulkan engine", item 3): the
// cull, commands and scatter passes recorded before the host's rendering select what si::gl's
// drawCrowdGpuCulled selects, and the indirect draw inside it gives si::gl's image, within the
// golden tolerance, on lavapipe with the validation layer on and silent; the views of one frame
// keep their own selections; the crowd's changes reach the GPU; what is not built is refused.
#include <glad/gl.h>

#include <cmath>
#include <cstring>

#include "core/pre_skin_lists.h"
#include "si/crowd/crowd_export.h"
#include "vk/vk_render_fixture.h"

namespace si {
namespace {

using namespace test;

class VulkanGpuDrivenTest : public VulkanRenderFixture {
 protected:
  // The renderer with a pre-skinning ring of `ring_bytes` (the default's: every instance
  // pre-skinned; 0: none).
  void start(uint64_t ring_bytes = vk::RendererDesc().gpu_driven_ring_bytes,
             uint32_t idle_frames = vk::RendererDesc().gpu_driven_idle_frames) {
    vk::RendererDesc rd;
    rd.gpu_driven = true;
    rd.gpu_driven_ring_bytes = ring_bytes;
    rd.gpu_driven_idle_frames = idle_frames;
    draws_ = ring_bytes != 0 ? 2 : 1;
    ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &renderer_, &id_));
  }

  // The host the frames render on: host_, or another (a multisampled one).
  examples::HeadlessVulkan& host() { return other_host_ != nullptr ? *other_host_ : host_; }

  // The occlusion scene's camera (wallCamera() tilted up by about 10 degrees: the wall fills
  // the lower part of the image, so a pyramid upside down, Vulkan's depth rows running from
  // the top, would not hide the crowd), with OpenGL's depth or reverse-Z.
  static Camera tiltedWallCamera(bool reverse_z) {
    const glm::dvec3 eye(0.0, 1.0, 2.0), target(0.0, 8.4, -40.0);
    return reverse_z
               ? Camera::lookAtReverseZ(eye, target, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f, 500.0f)
               : Camera::lookAt(eye, target, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f, 500.0f);
  }

  // Four frames of the wall crowd, each drawn by `crowd`'s own view without occlusion culling
  // and by `occluding` with it: the images within 0.1 % (written out when not), from the third
  // frame most of the crowd hidden. The last frame's occluded image into `last`.
  void expectOcclusionCulls(CrowdManager* crowd, const Camera& camera, const char* name,
                            std::vector<uint8_t>* last = nullptr) {
    CrowdView occluding;  // Its own history (visible last frame), apart from the plain view's.
    ASSERT_TRUE(occluding.init(*crowd).isOk());
    uint32_t slot = 0;
    for (int f = 0; f < 4; ++f) {
      SCOPED_TRACE(f);
      ASSERT_TRUE(crowd->advance(f == 0 ? 0.0 : 1.0 / 30.0).isOk());
      std::vector<uint8_t> expected, actual;
      Status s = frame(slot, {{&crowd->view(), camera}}, {&crowd->view()}, vk::DrawMode::kShaded,
                       &expected);
      ASSERT_TRUE(s.isOk()) << s.toString();
      vk::GpuDrivenCounts all, culled;
      ASSERT_TRUE(renderer_.readGpuDrivenCounts(id_, crowd->view(), &all).isOk());
      slot = (slot + 1) % 2;
      s = occlusionFrame(slot, occluding, camera, &actual);
      ASSERT_TRUE(s.isOk()) << s.toString();
      ASSERT_TRUE(renderer_.readGpuDrivenCounts(id_, occluding, &culled).isOk());
      slot = (slot + 1) % 2;
      const Diff diff = compare(actual, expected, nullptr);
      EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
      if (diff.share > 0.001) {
        const std::string base =
            ::testing::TempDir() + "si_vk_occlusion_" + name + "_" + std::to_string(f);
        EXPECT_TRUE(writePng(base + ".png", kSize, kSize, actual).isOk());
        EXPECT_TRUE(writePng(base + "_expected.png", kSize, kSize, expected).isOk());
      }
      std::printf("[ occlusion] %s frame %d: %llu of %llu triangles, %u of %u instances\n", name, f,
                  static_cast<unsigned long long>(culled.triangles),
                  static_cast<unsigned long long>(all.triangles), culled.visible, all.visible);
      if (f < 2) {
        EXPECT_EQ(culled.triangles, all.triangles);
      } else {
        EXPECT_LT(culled.triangles * 2, all.triangles);  // Most of the crowd is hidden.
        EXPECT_GE(culled.visible, 40u);                  // The wall's front row is drawn.
      }
      if (last != nullptr) *last = actual;
    }
  }

  // si::gl's GPU-driven image of `crowd`'s own view with `camera`, over kBackground (and its
  // draw's statistics, when asked).
  std::vector<uint8_t> glImage(const CrowdManager& crowd, const Camera& camera,
                               DrawStats* stats = nullptr) {
    Renderer gl;
    RendererDesc rd;
    rd.measure_gpu_time = stats != nullptr;  // The counts read back after the timer.
    EXPECT_TRUE(gl.init(info_, rd).isOk());
    CharacterId id;
    EXPECT_TRUE(gl.addCharacter(character(), palette(), &id).isOk());
    gl.clear(kBackground);
    const Status s = drawOnPath(gl, PathKind::kGpuDriven, crowd, camera, stats);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> image;
    EXPECT_TRUE(context_->readPixels(&image).isOk());
    gl.shutdown();
    return image;
  }

  // One frame in slot `slot`: the passes of each of `passes` (a view and its camera) before the
  // rendering, then the draws of `drawn` (views among them) in `mode`; the colour (shaded) and
  // depth read back.
  Status frame(uint32_t slot, const std::vector<std::pair<const CrowdView*, Camera>>& passes,
               const std::vector<const CrowdView*>& drawn, vk::DrawMode mode,
               std::vector<uint8_t>* image, std::vector<float>* depth = nullptr) {
    examples::HeadlessVulkan::Frame f;
    f.clear_color = kBackground;
    f.color = mode == vk::DrawMode::kShaded;
    if (!passes.empty()) f.clear_depth = clearDepth(passes[0].second);
    f.before = [&](VkCommandBuffer cmd) {
      Status s = renderer_.beginFrame(slot);
      pass_stats_.clear();
      for (const auto& [view, camera] : passes) {
        vk::PassStats stats;
        if (s.isOk()) s = renderer_.recordGpuDrivenPasses(cmd, id_, *view, camera, &stats);
        pass_stats_.push_back(stats);
      }
      return s;
    };
    vk::DrawTarget target{extent_, offset_};
    target.mode = mode;
    return host().render(f,
                         [&](VkCommandBuffer cmd) {
                           Status s = Status::ok();
                           for (const CrowdView* view : drawn) {
                             vk::DrawStats stats;
                             if (s.isOk())
                               s = renderer_.recordGpuDrivenDraw(cmd, target, id_, *view, &stats);
                             if (s.isOk()) {
                               EXPECT_EQ(stats.draw_calls, draws_) << "indirect draws";
                             }
                           }
                           return s;
                         },
                         {image, depth});
  }

  // The depth cleared for `camera`: the far plane, 0 under reverse-Z.
  static float clearDepth(const Camera& camera) {
    return camera.depth == DepthConvention::kReversedZeroToOne ? 0.0f : 1.0f;
  }

  // One frame of two-phase occlusion culling of `view` with `camera` in slot `slot`: the first
  // phase's passes and draw, then (the rendering ended) the depth pyramid and the second
  // phase's passes, then its draw in a rendering that loads the first's targets.
  Status occlusionFrame(uint32_t slot, const CrowdView& view, const Camera& camera,
                        std::vector<uint8_t>* image) {
    examples::HeadlessVulkan::Frame f;
    f.clear_color = kBackground;
    f.clear_depth = clearDepth(camera);
    f.before = [&](VkCommandBuffer cmd) {
      Status s = renderer_.beginFrame(slot);
      if (s.isOk())
        s = renderer_.recordGpuDrivenPasses(cmd, id_, view, camera, nullptr,
                                            vk::GpuCulling::kOcclusion);
      return s;
    };
    const vk::DrawTarget target{extent_, offset_};
    const auto draw = [&](VkCommandBuffer cmd) {
      return renderer_.recordGpuDrivenDraw(cmd, target, id_, view);
    };
    f.between = [&](VkCommandBuffer cmd, VkImageView depth) {
      vk::DepthSource source;
      source.view = depth;
      source.extent = extent_;
      source.offset = offset_;
      source.samples = host().samples();
      return renderer_.recordGpuDrivenOcclusion(cmd, id_, view, source);
    };
    f.after = draw;
    return host().render(f, draw, {image});
  }

  // Expects `image` within the golden tolerance of `gl_image`, and a crowd drawn.
  static void expectSameImage(const std::vector<uint8_t>& image,
                              const std::vector<uint8_t>& gl_image, const char* name) {
    const Diff diff = compare(image, gl_image, nullptr);
    EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
    std::vector<uint8_t> blank(image.size());
    for (size_t k = 0; k < blank.size(); k += 4)
      for (int c = 0; c < 4; ++c) blank[k + c] = uint8_t(std::lround(kBackground[c] * 255.0f));
    EXPECT_GT(compare(image, blank, nullptr).share, 0.02) << "the crowd is drawn";
    if (diff.share > kMaxDifferingShare) {
      const std::string base = ::testing::TempDir() + "si_vk_gpu_driven_" + name;
      EXPECT_TRUE(writePng(base + ".png", kSize, kSize, image).isOk());
      EXPECT_TRUE(writePng(base + "_gl.png", kSize, kSize, gl_image).isOk());
    }
  }

  vk::Renderer renderer_;
  vk::CharacterId id_;
  // Indirect draws a view's draw records: the pre-skinned entries' and the others'.
  uint32_t draws_ = 2;
  std::vector<vk::PassStats> pass_stats_;  // The last frame's passes', in order.
  examples::HeadlessVulkan* other_host_ = nullptr;  // Rendered on instead of host_ when set.
  // The area the frames draw (DrawTarget::extent and offset; the occlusion's depth the same).
  VkExtent2D extent_{kSize, kSize};
  VkOffset2D offset_{0, 0};
};

// The LOD rows and a close view cutting the near plane: the Vulkan passes select and draw what
// si::gl's GPU-driven path does, every instance pre-skinned into the ring, none (no ring), or the
// first few (a ring of 3 instances of the largest list: the others skinned in the vertex stage);
// a depth-only draw of the same passes writes the shaded draw's depth.
TEST_P(VulkanGpuDrivenTest, ThePassesAndTheDrawGiveOpenGlsImage) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  lodCrowd(&crowd);
  si::detail::PreSkinListData lists;
  si::detail::buildPreSkinLists(character().mesh, &lists);
  const Camera near_cut = Camera::lookAt({0.0, 1.2, -1.2}, {0.0, 1.0, -4.0}, glm::vec3(0, 1, 0),
                                         0.75f, 1.0f, 2.5f, 200.0f);
  const std::pair<const char*, Camera> views[] = {{"rows", lodCamera()}, {"near", near_cut}};
  const std::pair<const char*, uint64_t> rings[] = {
      {"ring", vk::RendererDesc().gpu_driven_ring_bytes},
      {"no ring", 0},
      {"small ring", uint64_t(lists.max_lod_vertices) * 16 * 3}};
  uint32_t slot = 0;
  for (const auto& [ring_name, ring_bytes] : rings)
    for (const auto& [name, camera] : views) {
      SCOPED_TRACE(name);
      SCOPED_TRACE(ring_name);
      if (&camera == &views[0].second) {
        ASSERT_NO_FATAL_FAILURE(start(ring_bytes));
      }
      DrawStats gl_stats;
      const std::vector<uint8_t> gl_image = glImage(crowd, camera, &gl_stats);
      std::vector<uint8_t> image;
      std::vector<float> depth, depth_only;
      Status s = frame(slot, {{&crowd.view(), camera}}, {&crowd.view()}, vk::DrawMode::kShaded,
                       &image, &depth);
      ASSERT_TRUE(s.isOk()) << s.toString();
      slot = (slot + 1) % 2;
      expectSameImage(image, gl_image, name);
      // The GPU's counts (read after the host's wait) are si::gl's: the same selection.
      vk::GpuDrivenCounts counts;
      ASSERT_TRUE(renderer_.readGpuDrivenCounts(id_, crowd.view(), &counts).isOk());
      EXPECT_EQ(counts.visible, gl_stats.gpu_visible);
      EXPECT_EQ(counts.instances, gl_stats.instances);
      EXPECT_EQ(counts.triangles, gl_stats.triangles);
      EXPECT_GT(counts.visible, 0u);
      if (ring_bytes == 0) {
        EXPECT_EQ(counts.pre_skinned_vertices, 0u);
        EXPECT_EQ(counts.vertex_shader_instances, counts.instances);
      } else if (&ring_bytes == &rings[0].second) {
        EXPECT_GT(counts.pre_skinned_vertices, 0u);
        EXPECT_EQ(counts.vertex_shader_instances, 0u) << "the ring holds every instance";
      } else {
        EXPECT_GT(counts.pre_skinned_vertices, 0u);
        EXPECT_LE(counts.pre_skinned_vertices, uint64_t(lists.max_lod_vertices) * 3);
        EXPECT_GT(counts.vertex_shader_instances, 0u) << "the rest in the vertex stage";
      }
      s = frame(slot, {{&crowd.view(), camera}}, {&crowd.view()}, vk::DrawMode::kDepthOnly, nullptr,
                &depth_only);
      ASSERT_TRUE(s.isOk()) << s.toString();
      slot = (slot + 1) % 2;
      expectSameDepth(depth, depth_only);
    }
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// Two-phase occlusion culling (GpuCulling::kOcclusion's passes and draw, then
// recordGpuDrivenOcclusion between two renderings, then the draw again): a dense wall of
// characters in front of a crowd, seen from below the wall's top, under OpenGL's depth and
// reverse-Z. Each frame's image is the
// one drawn without occlusion culling (si::vk's, and si::gl's); frame 0 has no history (the
// first phase draws nothing, the second everything), frame 1's first phase draws it all and
// its second learns what is hidden, and from frame 2 on most of the crowd behind the wall is
// not drawn, as with si::gl's occlusion culling.
TEST_P(VulkanGpuDrivenTest, OcclusionCullingDrawsTheSameImageWithFewerTriangles) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateWallCrowd(&crowd);
  std::vector<uint8_t> last;
  ASSERT_NO_FATAL_FAILURE(expectOcclusionCulls(&crowd, tiltedWallCamera(false), "OpenGL", &last));
  expectSameImage(last, glImage(crowd, tiltedWallCamera(false)), "occlusion");
  ASSERT_NO_FATAL_FAILURE(expectOcclusionCulls(&crowd, tiltedWallCamera(true), "reverse-Z"));
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// A multisampled target (RendererDesc::samples 4, the host's attachments of 4 samples resolved
// at the end of each rendering): occlusion culling reads the depth's samples (each pixel's
// farthest: hiz_copy_ms) and the resolved image is the one drawn without occlusion culling,
// with fewer triangles; it is antialiased (apart from the single-sampled image at the
// silhouettes); a depth pre-pass of it (depth_only_samples) writes the shaded draw's depth. A
// sample count the device cannot render is refused.
TEST_P(VulkanGpuDrivenTest, OcclusionCullingReadsAMultisampledDepth) {
  SI_START_VULKAN_HOST();
  examples::HeadlessVulkan multisampled;
  const Status made = multisampled.create(kSize, kSize, VK_SAMPLE_COUNT_4_BIT);
  ASSERT_TRUE(made.isOk()) << made.toString();
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateWallCrowd(&crowd);
  std::vector<uint8_t> single, resolved;
  ASSERT_NO_FATAL_FAILURE(start());
  ASSERT_NO_FATAL_FAILURE(expectOcclusionCulls(&crowd, tiltedWallCamera(false), "1x", &single));
  renderer_.shutdown();
  other_host_ = &multisampled;
  vk::RendererDesc rd;
  rd.gpu_driven = true;
  rd.samples = rd.depth_only_samples = VK_SAMPLE_COUNT_4_BIT;
  ASSERT_NO_FATAL_FAILURE(
      startRenderer(rd, character(), palette(), &renderer_, &id_, &multisampled));
  ASSERT_NO_FATAL_FAILURE(expectOcclusionCulls(&crowd, tiltedWallCamera(false), "4x", &resolved));
  const Diff antialiased = compare(resolved, single, nullptr);
  EXPECT_GT(antialiased.share, 0.002) << "the silhouettes' pixels are resolved from 4 samples";
  EXPECT_LT(antialiased.share, 0.3);
  // A depth pre-pass of the multisampled target (depth_only_samples): the shaded draw's depth
  // (sample 0 of each pixel, as the host resolves it).
  std::vector<uint8_t> unused;
  std::vector<float> depth, depth_only;
  const Camera camera = tiltedWallCamera(false);
  Status s =
      frame(0, {{&crowd.view(), camera}}, {&crowd.view()}, vk::DrawMode::kShaded, &unused, &depth);
  ASSERT_TRUE(s.isOk()) << s.toString();
  s = frame(1, {{&crowd.view(), camera}}, {&crowd.view()}, vk::DrawMode::kDepthOnly, nullptr,
            &depth_only);
  ASSERT_TRUE(s.isOk()) << s.toString();
  expectSameDepth(depth, depth_only);
  renderer_.shutdown();
  other_host_ = nullptr;
  // Three samples.
  vk::Renderer three;
  vk::RendererDesc bad = rd;
  bad.physical_device = host_.physicalDevice();
  bad.device = host_.device();
  bad.samples = VkSampleCountFlagBits(3);
  s = three.init(bad);
  EXPECT_EQ(s.code(), StatusCode::kUnsupported) << s.toString();
  EXPECT_NE(s.message().find("samples"), std::string::npos) << s.toString();
  EXPECT_TRUE(multisampled.messages().empty()) << multisampled.messages().front();
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// DrawTarget::offset and DepthSource::offset (a shadow atlas's cascade, a split screen's half):
// a view drawn into the quarter at (kSize / 2, kSize / 4) is the view drawn into the quarter at
// the origin, moved there, over the background; occlusion culling in that quarter reads the
// depth there (the same image, most of the crowd hidden).
TEST_P(VulkanGpuDrivenTest, DrawsLandAtTheTargetsOffset) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateWallCrowd(&crowd);
  const Camera camera = tiltedWallCamera(false);
  const uint32_t half = kSize / 2;
  extent_ = {half, half};
  std::vector<uint8_t> origin, moved;
  Status s = frame(0, {{&crowd.view(), camera}}, {&crowd.view()}, vk::DrawMode::kShaded, &origin);
  ASSERT_TRUE(s.isOk()) << s.toString();
  offset_ = {int32_t(half), int32_t(half / 2)};
  s = frame(1, {{&crowd.view(), camera}}, {&crowd.view()}, vk::DrawMode::kShaded, &moved);
  ASSERT_TRUE(s.isOk()) << s.toString();
  // The clear colour (within the unorm conversion's rounding).
  const auto background = [](const uint8_t* p) {
    for (int c = 0; c < 4; ++c)
      if (std::abs(int(p[c]) - int(std::lround(kBackground[c] * 255.0f))) > 1) return false;
    return true;
  };
  size_t apart = 0, drawn = 0, outside = 0;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const uint8_t* m = &moved[(size_t(y) * kSize + x) * 4];
      const bool in = x >= half && y >= half / 2 && y < half / 2 + half;
      if (!in) {
        outside += !background(m);
        continue;
      }
      const uint8_t* o = &origin[(size_t(y - half / 2) * kSize + (x - half)) * 4];
      apart += std::memcmp(m, o, 4) != 0;
      drawn += !background(o);
    }
  EXPECT_GT(drawn, size_t(half) * half / 20) << "the crowd is drawn";
  EXPECT_LE(apart, size_t(half) * half / 1000) << apart << " pixels of the quarter apart";
  EXPECT_EQ(outside, 0u) << "pixels drawn outside the target's area";
  ASSERT_NO_FATAL_FAILURE(expectOcclusionCulls(&crowd, camera, "offset"));
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// A frame the host records and throws away (discardFrame(): its swapchain went out of date, an
// error of its own): the passes it recorded are forgotten, so the next frame's passes copy the
// crowd's state in again and count, and draw, what si::gl's do. (Without it, the state copied
// in the thrown-away command buffer never reached the GPU.) Views of other crowds keep theirs.
TEST_P(VulkanGpuDrivenTest, AFrameThrownAwayIsForgotten) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  CrowdManager crowd, other;
  lodCrowd(&crowd);
  lodCrowd(&other);
  DrawStats gl_stats;
  const std::vector<uint8_t> gl_image = glImage(crowd, lodCamera(), &gl_stats);
  std::vector<uint8_t> image;
  // The other crowd's view, drawn and kept.
  ASSERT_TRUE(frame(1, {{&other.view(), lodCamera()}}, {}, vk::DrawMode::kShaded, &image).isOk());
  const uint32_t views_before = renderer_.gpuDrivenMemory().views;
  // Recorded, never submitted.
  Status s = host_.submit([&](VkCommandBuffer cmd) {
    Status r = renderer_.beginFrame(0);
    if (r.isOk()) r = renderer_.recordGpuDrivenPasses(cmd, id_, crowd.view(), lodCamera());
    return r.isOk() ? Status(StatusCode::kBackend, "thrown away") : r;
  });
  ASSERT_EQ(s.code(), StatusCode::kBackend) << s.toString();
  ASSERT_TRUE(renderer_.discardFrame().isOk());
  EXPECT_EQ(renderer_.gpuDrivenMemory().views, views_before) << "the other crowd's view is kept";
  EXPECT_EQ(renderer_.discardFrame().code(), StatusCode::kInvalidArgument) << "no frame begun";
  // The next frame's passes alone (no draw of what they count), then a frame drawn.
  s = frame(0, {{&crowd.view(), lodCamera()}}, {}, vk::DrawMode::kShaded, &image);
  ASSERT_TRUE(s.isOk()) << s.toString();
  vk::GpuDrivenCounts counts;
  ASSERT_TRUE(renderer_.readGpuDrivenCounts(id_, crowd.view(), &counts).isOk());
  EXPECT_EQ(counts.visible, gl_stats.gpu_visible);
  EXPECT_EQ(counts.triangles, gl_stats.triangles);
  if (counts.visible == gl_stats.gpu_visible && counts.triangles == gl_stats.triangles) {
    s = frame(1, {{&crowd.view(), lodCamera()}}, {&crowd.view()}, vk::DrawMode::kShaded, &image);
    ASSERT_TRUE(s.isOk()) << s.toString();
    expectSameImage(image, gl_image, "thrown_away");
  }
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// Two views' passes recorded before one rendering (a main view and a shadow view, as an engine
// records its compute before its passes): each draw shows its own view's selection, not the
// last passes'.
TEST_P(VulkanGpuDrivenTest, TheViewsOfOneFrameKeepTheirOwnSelections) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  CrowdManager crowd;
  lodCrowd(&crowd);
  CrowdView other;
  ASSERT_TRUE(other.init(crowd).isOk());
  const Camera main = lodCamera();
  const Camera elsewhere = Camera::lookAt({0.0, 1.2, -1.2}, {0.0, 1.0, -4.0}, glm::vec3(0, 1, 0),
                                          0.75f, 1.0f, 2.5f, 200.0f);
  const std::vector<uint8_t> gl_image = glImage(crowd, main);
  std::vector<uint8_t> image;
  const Status s = frame(0, {{&crowd.view(), main}, {&other, elsewhere}}, {&crowd.view()},
                         vk::DrawMode::kShaded, &image);
  ASSERT_TRUE(s.isOk()) << s.toString();
  expectSameImage(image, gl_image, "two_views");
  // The crowd's state is the views': uploaded once, by the first view's passes, and kept once.
  ASSERT_EQ(pass_stats_.size(), 2u);
  EXPECT_EQ(pass_stats_[0].state_bytes_uploaded, uint64_t(crowd.size()) * sizeof(GpuInstanceState));
  EXPECT_TRUE(pass_stats_[0].whole_upload);
  EXPECT_EQ(pass_stats_[1].state_bytes_uploaded, 0u) << "the second view shares the state";
  const vk::GpuDrivenMemory memory = renderer_.gpuDrivenMemory();
  EXPECT_EQ(memory.crowds, 1u);
  EXPECT_EQ(memory.views, 2u);
  EXPECT_GE(memory.crowd_bytes, uint64_t(crowd.size()) * sizeof(GpuInstanceState));
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// A view whose passes stop is freed after RendererDesc::gpu_driven_idle_frames frames, and its
// crowd's state once no view keeps it; a view that comes back starts over and draws as before.
TEST_P(VulkanGpuDrivenTest, IdleViewsAndCrowdsAreFreed) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start(vk::RendererDesc().gpu_driven_ring_bytes, 2));
  CrowdManager crowd;
  lodCrowd(&crowd);
  CrowdView other;
  ASSERT_TRUE(other.init(crowd).isOk());
  const Camera camera = lodCamera();
  const std::vector<uint8_t> gl_image = glImage(crowd, camera);
  std::vector<uint8_t> image;
  uint32_t slot = 0;
  const auto next = [&](const std::vector<std::pair<const CrowdView*, Camera>>& passes) {
    const std::vector<const CrowdView*> drawn =
        passes.empty() ? std::vector<const CrowdView*>()
                       : std::vector<const CrowdView*>{passes[0].first};
    const Status s = frame(slot, passes, drawn, vk::DrawMode::kShaded, &image);
    slot = (slot + 1) % 2;
    return s;
  };
  ASSERT_TRUE(next({{&crowd.view(), camera}, {&other, camera}}).isOk());
  EXPECT_EQ(renderer_.gpuDrivenMemory().views, 2u);
  for (int f = 0; f < 3; ++f) ASSERT_TRUE(next({{&crowd.view(), camera}}).isOk());
  vk::GpuDrivenMemory m = renderer_.gpuDrivenMemory();
  EXPECT_EQ(m.views, 1u) << "the other view is freed";
  EXPECT_EQ(m.crowds, 1u) << "the crowd's state is still kept";
  for (int f = 0; f < 3; ++f) ASSERT_TRUE(next({}).isOk());
  m = renderer_.gpuDrivenMemory();
  EXPECT_EQ(m.views, 0u);
  EXPECT_EQ(m.crowds, 0u);
  EXPECT_EQ(m.crowd_bytes + m.view_bytes, 0u);
  ASSERT_TRUE(next({{&crowd.view(), camera}}).isOk());
  ASSERT_EQ(pass_stats_.size(), 1u);
  EXPECT_TRUE(pass_stats_[0].whole_upload) << "the state copied in again";
  expectSameImage(image, gl_image, "back");
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// The crowd's changes between frames (instances removed and added, the clock moved on; one
// instance moved) reach the GPU: each frame draws what si::gl draws of the crowd as it is then,
// having copied in the whole state, nothing, or only the instance that moved.
TEST_P(VulkanGpuDrivenTest, TheCrowdsChangesReachTheGpu) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  CrowdManager crowd;
  lodCrowd(&crowd);
  const Camera camera = lodCamera();
  std::vector<uint8_t> first;
  ASSERT_TRUE(
      frame(0, {{&crowd.view(), camera}}, {&crowd.view()}, vk::DrawMode::kShaded, &first).isOk());
  // Half the instances gone, a new one near the camera, and time on.
  std::vector<InstanceHandle> handles;
  std::vector<GpuInstanceState> state;
  CrowdExport(crowd).state(&state, &handles);
  for (size_t k = 0; k < handles.size(); k += 2) ASSERT_TRUE(crowd.remove(handles[k]).isOk());
  InstanceDesc d;
  d.position = glm::dvec3(0.5, 0.0, -6.0);
  InstanceHandle added;
  ASSERT_TRUE(crowd.add(d, &added).isOk());
  ASSERT_TRUE(crowd.update(0.37, camera).isOk());
  const std::vector<uint8_t> gl_image = glImage(crowd, camera);
  EXPECT_GT(compare(first, gl_image, nullptr).share, 0.01) << "the crowd changed";
  std::vector<uint8_t> image;
  for (uint32_t slot : {1u, 0u}) {  // Both slots' staging, the second without an upload.
    SCOPED_TRACE(slot);
    ASSERT_TRUE(
        frame(slot, {{&crowd.view(), camera}}, {&crowd.view()}, vk::DrawMode::kShaded, &image)
            .isOk());
    expectSameImage(image, gl_image, "changed");
    ASSERT_EQ(pass_stats_.size(), 1u);
    EXPECT_EQ(pass_stats_[0].state_bytes_uploaded,
              slot == 1 ? uint64_t(crowd.size()) * sizeof(GpuInstanceState) : 0u);
  }
  // One instance moved across the view and grown: only its state is copied in.
  ASSERT_TRUE(
      crowd.setTransform(handles[1], glm::dvec3(-1.2, 0.0, -4.5), glm::quat(1, 0, 0, 0), 1.5f)
          .isOk());
  const std::vector<uint8_t> moved_gl = glImage(crowd, camera);
  EXPECT_GT(compare(moved_gl, gl_image, nullptr).share, 0.01) << "the instance moved";
  ASSERT_TRUE(
      frame(1, {{&crowd.view(), camera}}, {&crowd.view()}, vk::DrawMode::kShaded, &image).isOk());
  expectSameImage(image, moved_gl, "moved");
  ASSERT_EQ(pass_stats_.size(), 1u);
  EXPECT_FALSE(pass_stats_[0].whole_upload);
  EXPECT_EQ(pass_stats_[0].upload_regions, 1u);
  EXPECT_EQ(pass_stats_[0].state_bytes_uploaded, sizeof(GpuInstanceState));
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// What is not built on Vulkan yet, or asked wrongly, is refused by name, recording nothing.
TEST_P(VulkanGpuDrivenTest, RefusalsAreNamed) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  lodCrowd(&crowd);
  {  // A renderer not made for the path.
    vk::Renderer plain;
    vk::CharacterId id;
    ASSERT_NO_FATAL_FAILURE(startRenderer(vk::RendererDesc(), &plain, &id));
    const Status s = host_.submit([&](VkCommandBuffer cmd) {
      EXPECT_TRUE(plain.beginFrame(0).isOk());
      return plain.recordGpuDrivenPasses(cmd, id, crowd.view(), lodCamera());
    });
    EXPECT_EQ(s.code(), StatusCode::kUnsupported) << s.toString();
    EXPECT_NE(s.message().find("gpu_driven"), std::string::npos) << s.toString();
  }
  {  // A ring that does not hold one instance of the largest list.
    ASSERT_NO_FATAL_FAILURE(start(16));
    std::vector<uint8_t> image;
    const Status s = frame(0, {{&crowd.view(), lodCamera()}}, {}, vk::DrawMode::kShaded, &image);
    EXPECT_EQ(s.code(), StatusCode::kLimitExceeded) << s.toString();
    EXPECT_NE(s.message().find("gpu_driven_ring_bytes"), std::string::npos) << s.toString();
  }
  ASSERT_NO_FATAL_FAILURE(start());
  // A draw without this frame's passes.
  std::vector<uint8_t> image;
  Status s = frame(0, {}, {&crowd.view()}, vk::DrawMode::kShaded, &image);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
  EXPECT_NE(s.message().find("recordGpuDrivenPasses"), std::string::npos) << s.toString();
  // A draw at a negative offset (no passes: a frame recorded and never submitted leaves the
  // crowd's state on the GPU behind what the renderer copied).
  offset_ = {-1, 0};
  s = frame(0, {}, {&crowd.view()}, vk::DrawMode::kShaded, &image);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
  EXPECT_NE(s.message().find("offset"), std::string::npos) << s.toString();
  offset_ = {0, 0};
  // Passes of one frame do not serve the next frame in the same slot.
  ASSERT_TRUE(
      frame(0, {{&crowd.view(), lodCamera()}}, {&crowd.view()}, vk::DrawMode::kShaded, &image)
          .isOk());
  s = frame(0, {}, {&crowd.view()}, vk::DrawMode::kShaded, &image);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
  // Occlusion culling's second phase: only after a first phase of this frame, once, with a
  // depth compute shaders can read, its pyramid within maxImageDimension2D.
  {
    VkPhysicalDeviceProperties props{};
    vkGetPhysicalDeviceProperties(host_.physicalDevice(), &props);
    const VkImageView some_view = reinterpret_cast<VkImageView>(uintptr_t(1));  // Never read.
    const auto second = [&](vk::GpuCulling culling, const vk::DepthSource& depth) {
      return host_.submit([&](VkCommandBuffer cmd) {
        EXPECT_TRUE(renderer_.beginFrame(0).isOk());
        Status first =
            renderer_.recordGpuDrivenPasses(cmd, id_, crowd.view(), lodCamera(), nullptr, culling);
        return first.isOk() ? renderer_.recordGpuDrivenOcclusion(cmd, id_, crowd.view(), depth)
                            : first;
      });
    };
    vk::DepthSource depth;
    depth.view = some_view;
    depth.extent = {kSize, kSize};
    s = second(vk::GpuCulling::kFrustum, depth);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
    EXPECT_NE(s.message().find("first phase"), std::string::npos) << s.toString();
    vk::DepthSource attachment = depth;
    attachment.layout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    s = second(vk::GpuCulling::kOcclusion, attachment);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
    EXPECT_NE(s.message().find("layout"), std::string::npos) << s.toString();
    vk::DepthSource negative = depth;
    negative.offset = {0, -1};
    s = second(vk::GpuCulling::kOcclusion, negative);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
    EXPECT_NE(s.message().find("offset"), std::string::npos) << s.toString();
    vk::DepthSource huge = depth;
    huge.extent = {props.limits.maxImageDimension2D + 1, 1};
    s = second(vk::GpuCulling::kOcclusion, huge);
    EXPECT_EQ(s.code(), StatusCode::kLimitExceeded) << s.toString();
    EXPECT_NE(s.message().find("maxImageDimension2D"), std::string::npos) << s.toString();
  }
  // A crowd of more sub-meshes than the character's.
  {
    CrowdManager wider;
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = uint32_t(character().mesh.sub_meshes.size()) + 1;
    cd.lod_count = 1;
    ASSERT_TRUE(wider.init(cd).isOk());
    s = host_.submit([&](VkCommandBuffer cmd) {
      EXPECT_TRUE(renderer_.beginFrame(0).isOk());
      return renderer_.recordGpuDrivenPasses(cmd, id_, wider.view(), lodCamera());
    });
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
    EXPECT_NE(s.message().find("sub-meshes"), std::string::npos) << s.toString();
  }
  // A detached view.
  CrowdView detached;
  s = host_.submit([&](VkCommandBuffer cmd) {
    EXPECT_TRUE(renderer_.beginFrame(0).isOk());
    return renderer_.recordGpuDrivenPasses(cmd, id_, detached, lodCamera());
  });
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

INSTANTIATE_TEST_SUITE_P(Backends, VulkanGpuDrivenTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
