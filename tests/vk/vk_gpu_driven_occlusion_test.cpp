// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The Vulkan back-end's GPU-driven path with two-phase occlusion culling (issue "The crowd in a
// Vulkan engine", item 3): GpuCulling::kOcclusion's passes and draw, the depth pyramid and the
// second phase recorded between two renderings, give the image drawn without occlusion culling
// with fewer triangles, under OpenGL's depth and reverse-Z, multisampled, and in a target's
// quarter, on lavapipe with the validation layer on and silent.
#include <glad/gl.h>

#include <cstdio>
#include <string>
#include <vector>

#include "vk/vk_gpu_driven_fixture.h"

namespace si {
namespace {

using namespace test;

class VulkanGpuDrivenOcclusionTest : public VulkanGpuDrivenFixture {
 protected:
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
        EXPECT_LT(culled.triangles, all.triangles);
        EXPECT_LT(culled.visible * 2, all.visible);  // Most of the crowd is hidden.
        EXPECT_GE(culled.visible, 40u);              // The wall's front row is drawn.
      }
      if (last != nullptr) *last = actual;
    }
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
};

// Two-phase occlusion culling (GpuCulling::kOcclusion's passes and draw, then
// recordGpuDrivenOcclusion between two renderings, then the draw again): a dense wall of
// characters in front of a crowd, seen from below the wall's top, under OpenGL's depth and
// reverse-Z. Each frame's image is the
// one drawn without occlusion culling (si::vk's, and si::gl's); frame 0 has no history (the
// first phase draws nothing, the second everything), frame 1's first phase draws it all and
// its second learns what is hidden, and from frame 2 on most of the crowd behind the wall is
// not drawn, as with si::gl's occlusion culling.
TEST_P(VulkanGpuDrivenOcclusionTest, OcclusionCullingDrawsTheSameImageWithFewerTriangles) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  CrowdManager crowd;
  makeCoarseCrowd(&crowd);
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
TEST_P(VulkanGpuDrivenOcclusionTest, OcclusionCullingReadsAMultisampledDepth) {
  SI_START_VULKAN_HOST();
  examples::HeadlessVulkan multisampled;
  const Status made = multisampled.create(kSize, kSize, VK_SAMPLE_COUNT_4_BIT);
  ASSERT_TRUE(made.isOk()) << made.toString();
  CrowdManager crowd;
  makeCoarseCrowd(&crowd);
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
TEST_P(VulkanGpuDrivenOcclusionTest, DrawsLandAtTheTargetsOffset) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  CrowdManager crowd;
  makeCoarseCrowd(&crowd);
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

INSTANTIATE_TEST_SUITE_P(Backends, VulkanGpuDrivenOcclusionTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
