// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The host's depth conventions and depth-only views on the Vulkan back-end (issue "The crowd in
// a Vulkan engine"): under OpenGL's -1 to 1 projection (mapped), a zero-to-one one and reverse-Z
// with an infinite far plane, shaded and depth-only draws give si::gl's image and, converted
// back to distances along the view axis, its depth; a y-flipped projection draws the mirrored
// image with the same faces culled; the host's depth test and depth bias are applied.
#include <glad/gl.h>

#include <algorithm>

#include "render/depth_distances.h"
#include "vk/vk_render_fixture.h"

namespace si {
namespace {

using namespace test;

class VulkanDepthTest : public VulkanRenderFixture {
 protected:
  // Starts the renderer and a batcher for it.
  void start(vk::RendererDesc rd = {}) {
    ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &renderer_, &id_));
    ASSERT_TRUE(batcher_.init(renderer_.batchLimits()).isOk());
  }

  // One frame (slot 0, the host waits for each) of `crowd`'s view drawn with `camera` into
  // `target`'s mode, the depth cleared to `clear_depth`: its colour (shaded) and depth.
  void draw(const CrowdManager& crowd, const Camera& camera, const vk::DrawTarget& target,
            float clear_depth, std::vector<uint8_t>* image, std::vector<float>* depth) {
    examples::HeadlessVulkan::Frame frame;
    frame.clear_color = kBackground;
    frame.clear_depth = clear_depth;
    frame.color = target.mode == vk::DrawMode::kShaded;
    const Status s = host_.render(frame,
                                  [&](VkCommandBuffer cmd) {
                                    const Status begun = renderer_.beginFrame(0);
                                    if (!begun.isOk()) return begun;
                                    return renderer_.recordDraw(cmd, target, id_, crowd.view(),
                                                                batcher_, camera);
                                  },
                                  {image, depth});
    ASSERT_TRUE(s.isOk()) << s.toString();
  }

  static vk::DrawTarget shaded() { return vk::DrawTarget{{kSize, kSize}}; }
  static vk::DrawTarget depthOnly() {
    vk::DrawTarget t = shaded();
    t.mode = vk::DrawMode::kDepthOnly;
    return t;
  }

  static constexpr glm::vec4 kBackground = glm::vec4(0.2f, 0.25f, 0.3f, 1.0f);
  vk::Renderer renderer_;
  vk::CharacterId id_;
  InstanceBatcher batcher_;
};

// The context's depth, rows top to bottom as HeadlessContext::readPixels gives the colour (and
// the Vulkan host reads its flipped viewport's images).
std::vector<float> readGlDepth() {
  std::vector<float> z(size_t(kSize) * kSize), rows(z.size());
  glReadPixels(0, 0, GLsizei(kSize), GLsizei(kSize), GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
  for (size_t y = 0; y < kSize; ++y)
    std::copy_n(z.begin() + (kSize - 1 - y) * kSize, kSize, rows.begin() + y * kSize);
  return rows;
}

TEST_P(VulkanDepthTest, EveryConventionDrawsOpenGlsImageAndDepthShadedAndDepthOnly) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  const Camera standard = lodCamera();
  CrowdManager crowd;
  lodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.0, standard).isOk());
  // si::gl's image and depth: the vertex-shader path (the instanced path) on this context.
  Renderer gl;
  makeRenderer(&gl);
  gl.clear(kBackground, 1.0f);
  const Status drawn = drawOnPath(gl, PathKind::kInstanced, crowd, standard, nullptr);
  ASSERT_TRUE(drawn.isOk()) << drawn.toString();
  std::vector<uint8_t> gl_image;
  ASSERT_TRUE(context_->readPixels(&gl_image).isOk());
  const std::vector<float> gl_distance = viewDistances(readGlDepth(), standard);
  for (DepthConvention convention :
       {DepthConvention::kNegativeOneToOne, DepthConvention::kZeroToOne,
        DepthConvention::kReversedZeroToOne}) {
    SCOPED_TRACE(depthConventionName(convention));
    const Camera camera = withConvention(standard, convention, 0.9f, 0.1f, 500.0f);
    CrowdManager seen;  // The same crowd selected by this camera: the same instances and LODs.
    lodCrowd(&seen);
    ASSERT_TRUE(seen.update(0.0, camera).isOk());
    const float clear_depth = convention == DepthConvention::kReversedZeroToOne ? 0.0f : 1.0f;
    std::vector<uint8_t> image;
    std::vector<float> depth, depth_only;
    ASSERT_NO_FATAL_FAILURE(draw(seen, camera, shaded(), clear_depth, &image, &depth));
    ASSERT_NO_FATAL_FAILURE(draw(seen, camera, depthOnly(), clear_depth, nullptr, &depth_only));
    const Diff diff = compare(image, gl_image, nullptr);
    EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
    for (const auto& [name, d] :
         {std::pair{"shaded", &depth}, std::pair{"depth only", &depth_only}}) {
      const DistanceDiff apart = compareDistances(viewDistances(*d, camera), gl_distance);
      EXPECT_GT(apart.covered, 2000u) << name;
      EXPECT_LE(apart.apart, apart.covered / 200)
          << name << ": " << apart.apart << " of " << apart.covered;
    }
  }
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// A projection that mirrors the image (y flipped, as engines draw render textures) draws the
// standard image upside down: the same faces culled, turned by the front face it sets.
TEST_P(VulkanDepthTest, AFlippedProjectionDrawsTheMirroredImage) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  CrowdManager crowd;
  lodCrowd(&crowd);
  Camera flipped = lodCamera();
  flipped.projection =
      glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, -1.0f, 1.0f)) * flipped.projection;
  ASSERT_TRUE(flipped.flipsWinding());
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  std::vector<uint8_t> standard, mirrored;
  ASSERT_NO_FATAL_FAILURE(draw(crowd, lodCamera(), shaded(), 1.0f, &standard, nullptr));
  ASSERT_NO_FATAL_FAILURE(draw(crowd, flipped, shaded(), 1.0f, &mirrored, nullptr));
  std::vector<uint8_t> unflipped(mirrored.size());
  const size_t row = size_t(kSize) * 4;
  for (size_t y = 0; y < kSize; ++y)
    std::copy_n(mirrored.begin() + (kSize - 1 - y) * row, row, unflipped.begin() + y * row);
  const Diff diff = compare(unflipped, standard, nullptr);
  EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// DrawTarget's depth test and bias reach the draws: VK_COMPARE_OP_NEVER draws nothing, and a
// slope bias moves every covered pixel of a depth-only view back.
TEST_P(VulkanDepthTest, TheHostsDepthTestAndBiasAreApplied) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(start());
  CrowdManager crowd;
  lodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  vk::DrawTarget never = shaded();
  never.depth_compare = VK_COMPARE_OP_NEVER;
  std::vector<uint8_t> image, background;
  ASSERT_NO_FATAL_FAILURE(draw(crowd, lodCamera(), shaded(), 1.0f, &image, nullptr));
  ASSERT_NO_FATAL_FAILURE(draw(crowd, lodCamera(), never, 1.0f, &background, nullptr));
  EXPECT_GT(compare(image, background, nullptr).share, 0.02) << "the crowd is drawn";
  for (size_t k = 0; k < background.size(); k += 4)
    ASSERT_EQ(background[k], uint8_t(std::lround(kBackground.r * 255.0f))) << "pixel " << k / 4;
  std::vector<float> depth, biased;
  vk::DrawTarget bias = depthOnly();
  bias.depth_bias_slope = 4.0f;
  ASSERT_NO_FATAL_FAILURE(draw(crowd, lodCamera(), depthOnly(), 1.0f, nullptr, &depth));
  ASSERT_NO_FATAL_FAILURE(draw(crowd, lodCamera(), bias, 1.0f, nullptr, &biased));
  size_t covered = 0, behind = 0, before = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    if (depth[i] >= 1.0f) continue;
    ++covered;
    behind += biased[i] > depth[i];
    before += biased[i] < depth[i];
  }
  EXPECT_GT(covered, 2000u);
  EXPECT_EQ(before, 0u);
  EXPECT_GT(behind, covered / 2) << behind << " of " << covered;
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

INSTANTIATE_TEST_SUITE_P(Backends, VulkanDepthTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
