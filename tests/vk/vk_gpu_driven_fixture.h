// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the Vulkan GPU-driven path's render tests share (vk_gpu_driven_test.cpp and
// vk_gpu_driven_occlusion_test.cpp): a GPU-driven renderer, si::gl's image of the same crowd,
// one frame of passes and draws recorded around the host's rendering, and the golden-tolerance
// check against si::gl's image.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "vk/vk_render_fixture.h"

namespace si::test {

class VulkanGpuDrivenFixture : public VulkanRenderFixture {
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

  // Expects `image` within the golden tolerance of `gl_image`, and a crowd drawn.
  static void expectSameImage(const std::vector<uint8_t>& image,
                              const std::vector<uint8_t>& gl_image, const char* name) {
    const Diff diff = compare(image, gl_image, nullptr);
    EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
    EXPECT_GT(compare(image, blankImage(image), nullptr).share, 0.02) << "the crowd is drawn";
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
  std::vector<vk::PassStats> pass_stats_;           // The last frame's passes', in order.
  examples::HeadlessVulkan* other_host_ = nullptr;  // Rendered on instead of host_ when set.
  // The area the frames draw (DrawTarget::extent and offset; the occlusion's depth the same).
  VkExtent2D extent_{kSize, kSize};
  VkOffset2D offset_{0, 0};
};

}  // namespace si::test
