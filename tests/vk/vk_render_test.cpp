// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The Vulkan back-end drawing into an engine-like host's frame (issue "The crowd in a Vulkan
// engine"): on lavapipe (or any Vulkan 1.3 device), with the validation layer on and silent, the
// vertex-shader path draws the scene si::Renderer's vertex-shader path draws on this machine's
// OpenGL, within the golden tolerance. SI_REQUIRE_VULKAN=1 turns a missing device into a failure.
#include "vk/vk_render_fixture.h"

namespace si {
namespace {

using namespace test;

class VulkanRenderTest : public VulkanRenderFixture {};

TEST_P(VulkanRenderTest, TheVertexShaderPathDrawsWhatOpenGlDraws) {
  SI_START_VULKAN_HOST();
  examples::HeadlessVulkan& host = host_;
  CrowdManager crowd;
  lodCrowd(&crowd);
  vk::Renderer r;
  vk::RendererDesc rd;
  // Slots of an odd size: the second view's slot still starts where a dynamic offset may (the
  // validation layer reports a misaligned one).
  rd.ring_bytes_per_frame = (1u << 20) + 100;
  vk::CharacterId id;
  ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &r, &id));
  Status s;
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  const glm::vec4 background(0.2f, 0.25f, 0.3f, 1.0f);
  // The three rows at their LODs; and close up, the near plane cutting the nearest characters,
  // whose depth is in OpenGL's lower half (-1 to 0) and must be mapped to Vulkan's 0 to 1.
  const Camera near_cut = Camera::lookAt({0.0, 1.2, -1.2}, {0.0, 1.0, -4.0}, glm::vec3(0, 1, 0),
                                         0.75f, 1.0f, 2.5f, 200.0f);
  const std::pair<const char*, Camera> views[] = {{"LOD rows", lodCamera()},
                                                  {"near plane", near_cut}};
  uint32_t slot = 0;
  for (const auto& [name, camera] : views) {
    SCOPED_TRACE(name);
    const std::vector<uint8_t> gl_image =
        drawCrowdImage(character(), palette(), crowd, camera, false);
    std::vector<uint8_t> image;
    vk::DrawStats stats;
    examples::HeadlessVulkan::Frame frame;
    frame.clear_color = background;
    s = host.render(
        frame,
        [&](VkCommandBuffer cmd) {
          const Status begun = r.beginFrame(slot);
          if (!begun.isOk()) return begun;
          return r.recordDraw(cmd, vk::DrawTarget{{kSize, kSize}}, id, crowd.view(), batcher,
                              camera, &stats);
        },
        {&image});
    ASSERT_TRUE(s.isOk()) << s.toString();
    ++slot;
    EXPECT_GT(stats.draw_calls, 0u);
    EXPECT_EQ(stats.instances, crowd.view().bucketOffsets().back()) << "every instance-draw";
    const Diff diff = compare(image, gl_image, nullptr);
    EXPECT_LE(diff.share, kMaxDifferingShare);
    EXPECT_GT(compare(image, blankImage(image, background), nullptr).share, 0.02)
        << "the crowd is drawn";
    if (diff.share > kMaxDifferingShare) {
      EXPECT_TRUE(writePng(::testing::TempDir() + "si_vk_image.png", kSize, kSize, image).isOk());
      EXPECT_TRUE(
          writePng(::testing::TempDir() + "si_vk_gl_image.png", kSize, kSize, gl_image).isOk());
    }
  }
  EXPECT_TRUE(host.messages().empty()) << messages();
  r.shutdown();
}

// What the back-end cannot do yet, or is asked wrongly, is refused by name and records nothing.
TEST_P(VulkanRenderTest, RefusalsAreNamed) {
  vk::Renderer r;
  vk::RendererDesc rd;
  EXPECT_EQ(r.init(rd).code(), StatusCode::kInvalidArgument) << "no device";
  SI_START_VULKAN_HOST();
  examples::HeadlessVulkan& host = host_;
  rd.physical_device = host.physicalDevice();
  rd.device = host.device();
  for (uint32_t frames : {0u, 9u}) {
    rd.frames_in_flight = frames;
    const Status s = r.init(rd);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << frames;
    EXPECT_NE(s.message().find("frames_in_flight"), std::string::npos) << s.toString();
  }
  for (float share : {-0.1f, 1.5f}) {
    rd.morph_lod_share = share;
    const Status s = r.init(rd);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << share;
    EXPECT_NE(s.message().find("morph_lod_share"), std::string::npos) << s.toString();
  }
  rd.morph_lod_share = 0.5f;
  rd.frames_in_flight = 8;
  rd.ring_bytes_per_frame = uint64_t(1) << 30;
  Status s = r.init(rd);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded) << "past 32-bit dynamic offsets";
  rd.frames_in_flight = 2;
  rd.ring_bytes_per_frame = 65519;
  EXPECT_EQ(r.init(rd).code(), StatusCode::kInvalidArgument) << "less than one batch";
  rd.ring_bytes_per_frame = 65520;  // One batch of records: the defaults do not fit after it.
  ASSERT_TRUE(r.init(rd).isOk());
  // A palette baked for another skeleton (one joint fewer).
  BakedPalette other = palette();
  other.skeleton_to_palette.pop_back();
  vk::CharacterId id;
  s = r.addCharacter(character(), other, &id);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
  EXPECT_NE(s.message().find("palette"), std::string::npos) << s.toString();
  ASSERT_TRUE(r.addCharacter(character(), palette(), &id).isOk());
  CrowdManager crowd;
  lodCrowd(&crowd);
  // 900 in view: their records pass one batch's bytes, so the ring's region cannot hold them.
  for (int k = 0; k < 900; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3((k % 30 - 14.5) * 1.5, 0.0, -10.0 - 1.5 * (k / 30));
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
  }
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  ASSERT_GT(batcher.recordBufferBound(crowd.view()), 65520u);
  std::vector<uint8_t> image;
  const auto frame = [&] {
    return host.render(
        {},
        [&](VkCommandBuffer cmd) {
          return r.recordDraw(cmd, vk::DrawTarget{{kSize, kSize}}, id, crowd.view(), batcher,
                              lodCamera());
        },
        {&image});
  };
  s = frame();
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("recordUploads"), std::string::npos) << s.toString();
  ASSERT_TRUE(host.submit([&](VkCommandBuffer cmd) { return r.recordUploads(cmd); }).isOk());
  r.uploadsComplete();
  s = frame();
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("beginFrame"), std::string::npos) << s.toString();
  EXPECT_EQ(r.beginFrame(2).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(r.beginFrame(1).isOk());
  s = frame();
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("ring_bytes_per_frame"), std::string::npos) << s.toString();
  // A target with no area, a mode or depth test that does not exist.
  vk::DrawTarget empty, no_mode{{kSize, kSize}}, no_compare{{kSize, kSize}};
  no_mode.mode = vk::DrawMode(7);
  no_compare.depth_compare = VkCompareOp(8);
  for (const auto& [target, word] : {std::pair{empty, "extent"}, std::pair{no_mode, "mode"},
                                     std::pair{no_compare, "depth_compare"}}) {
    s = r.recordDraw(VK_NULL_HANDLE, target, id, crowd.view(), batcher, lodCamera());
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << word;
    EXPECT_NE(s.message().find(word), std::string::npos) << s.toString();
  }
  EXPECT_EQ(r.recordDraw(VK_NULL_HANDLE, vk::DrawTarget{{kSize, kSize}}, vk::CharacterId{7},
                         crowd.view(), batcher, lodCamera())
                .code(),
            StatusCode::kInvalidArgument);
  EXPECT_TRUE(host.messages().empty()) << messages();
  r.shutdown();
}

// The OpenGL image from EGL: surfaceless (llvmpipe without a GPU), or the device platform where
// it reaches a GPU's driver (on llvmpipe the fixture skips it, as the other render tests).
INSTANTIATE_TEST_SUITE_P(Backends, VulkanRenderTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
