// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the Vulkan render tests share: the OpenGL fixture (for si::gl's reference images), the
// engine-like Vulkan host of the vulkan_host example (skipped, or failed with SI_REQUIRE_VULKAN=1,
// where the machine has no Vulkan 1.3 device), a vk::Renderer with the embedded character uploaded,
// and the LOD rows' crowd.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "render/render_fixture.h"
#include "si/gl/motion_target.h"
#include "si/vk/renderer.h"
#include "vulkan_host/headless_vulkan.h"

namespace si::test {

class VulkanRenderFixture : public RenderTest {
 public:
  // The background of the render tests' images (drawCrowdImage's).
  static constexpr glm::vec4 kBackground = glm::vec4(0.2f, 0.25f, 0.3f, 1.0f);

  // An RGBA8 image as large as `like`, of `colour` alone: what a frame that drew nothing reads
  // back.
  static std::vector<uint8_t> blankImage(const std::vector<uint8_t>& like,
                                         const glm::vec4& colour = kBackground) {
    std::vector<uint8_t> blank(like.size());
    for (size_t k = 0; k < blank.size(); k += 4)
      for (int c = 0; c < 4; ++c) blank[k + c] = uint8_t(std::lround(colour[c] * 255.0f));
    return blank;
  }

 protected:
  // Creates host_; false (the test skipped, or failed under SI_REQUIRE_VULKAN) without a device.
  bool startHost() {
    const Status created = host_.create(kSize, kSize);
    if (created.isOk()) {
      std::printf("[ vulkan ] %s, validation %s\n", host_.deviceName().c_str(),
                  host_.validation() ? "on" : "not installed");
      return true;
    }
    if (std::getenv("SI_REQUIRE_VULKAN") != nullptr) {
      ADD_FAILURE() << created.toString();
    } else {
      skip_reason_ = created.toString();
    }
    return false;
  }

  // `desc` on host_'s device, the embedded character added and its uploads submitted.
  void startRenderer(const vk::RendererDesc& desc, vk::Renderer* r, vk::CharacterId* id) {
    startRenderer(desc, character(), palette(), r, id);
  }
  // The same with `c`, baked as `baked`, on `host` (host_ when null).
  void startRenderer(vk::RendererDesc desc, const Character& c, const BakedPalette& baked,
                     vk::Renderer* r, vk::CharacterId* id,
                     examples::HeadlessVulkan* host = nullptr) {
    examples::HeadlessVulkan& h = host != nullptr ? *host : host_;
    desc.physical_device = h.physicalDevice();
    desc.device = h.device();
    Status s = r->init(desc);
    ASSERT_TRUE(s.isOk()) << s.toString();
    s = r->addCharacter(c, baked, id);
    ASSERT_TRUE(s.isOk()) << s.toString();
    s = h.submit([&](VkCommandBuffer cmd) { return r->recordUploads(cmd); });
    ASSERT_TRUE(s.isOk()) << s.toString();
    r->uploadsComplete();
  }

  // `crowd`'s last selection of `character` (baked as `palette`) drawn with `camera` over
  // kBackground by a fresh vk::Renderer on host_ (the vertex-shader path, shaded): the image.
  std::vector<uint8_t> vulkanImage(const Character& character, const BakedPalette& palette,
                                   const CrowdManager& crowd, const Camera& camera) {
    vk::Renderer r;
    vk::CharacterId id;
    startRenderer(vk::RendererDesc(), character, palette, &r, &id);
    InstanceBatcher batcher;
    EXPECT_TRUE(batcher.init(r.batchLimits()).isOk());
    examples::HeadlessVulkan::Frame frame;
    frame.clear_color = kBackground;
    std::vector<uint8_t> image;
    const Status s = host_.render(frame,
                                  [&](VkCommandBuffer cmd) {
                                    const Status begun = r.beginFrame(0);
                                    if (!begun.isOk()) return begun;
                                    return r.recordDraw(cmd, vk::DrawTarget{{kSize, kSize}}, id,
                                                        crowd.view(), batcher, camera);
                                  },
                                  {&image});
    EXPECT_TRUE(s.isOk()) << s.toString();
    return image;
  }

  // si::gl's renderer of `desc` on the test's context, the embedded character added (`*id`).
  void startGl(const RendererDesc& desc, Renderer* gl, CharacterId* id) {
    ASSERT_TRUE(gl->init(info_, desc).isOk());
    ASSERT_TRUE(gl->addCharacter(character(), palette(), id).isOk());
  }

  // `crowd`'s last selection of the embedded character drawn with `camera` by si::gl's
  // vertex-shader path with motion vectors into a MotionTarget over kBackground: its colour and
  // motion (rows bottom to top, as MotionTarget reads them).
  void glMotion(const CrowdManager& crowd, const Camera& camera, std::vector<uint8_t>* image,
                std::vector<glm::vec2>* motion) {
    RendererDesc rd;
    rd.motion_vectors = true;
    Renderer gl;
    CharacterId id;
    ASSERT_NO_FATAL_FAILURE(startGl(rd, &gl, &id));
    MotionTarget target;
    ASSERT_TRUE(target.create(kSize, kSize).isOk());
    target.clear(kBackground);
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(gl.batchLimits()).isOk());
    const Status drawn = gl.drawCrowd(id, crowd.view(), batcher, camera, nullptr);
    target.restore();
    ASSERT_TRUE(drawn.isOk()) << drawn.toString();
    ASSERT_TRUE(target.readMotion(motion).isOk());
    ASSERT_TRUE(target.readColor(image).isOk());
  }

  // One frame of `crowd` with `camera`: si::gl's drawCrowdGpuCulled (`gl`, `gl_id`; pre-skinned
  // or in the vertex stage) into `target` over kBackground, its colour and motion into
  // `gl_image` and `gl_motion` (rows bottom to top); then `r`'s GPU-driven passes and shaded draw
  // of character `id` in frame slot `slot`, its colour and motion into `image` and `motion`.
  void drivenMotionFrame(Renderer& gl, CharacterId gl_id, MotionTarget& target, vk::Renderer& r,
                         vk::CharacterId id, uint32_t slot, const CrowdManager& crowd,
                         const Camera& camera, bool pre_skinned, std::vector<uint8_t>* gl_image,
                         std::vector<glm::vec2>* gl_motion, std::vector<uint8_t>* image,
                         std::vector<glm::vec2>* motion) {
    target.clear(kBackground);
    const Status drawn =
        gl.drawCrowdGpuCulled(gl_id, crowd.view(), camera, nullptr,
                              pre_skinned ? DrawMode::kDefault : DrawMode::kSkinned);
    target.restore();
    ASSERT_TRUE(drawn.isOk()) << drawn.toString();
    ASSERT_TRUE(target.readMotion(gl_motion).isOk());
    ASSERT_TRUE(target.readColor(gl_image).isOk());
    examples::HeadlessVulkan::Frame frame;
    frame.clear_color = kBackground;
    frame.motion = true;
    frame.before = [&](VkCommandBuffer cmd) {
      const Status begun = r.beginFrame(slot);
      return begun.isOk() ? r.recordGpuDrivenPasses(cmd, id, crowd.view(), camera) : begun;
    };
    const Status s = host_.render(
        frame,
        [&](VkCommandBuffer cmd) {
          return r.recordGpuDrivenDraw(cmd, vk::DrawTarget{{kSize, kSize}}, id, crowd.view());
        },
        {image, nullptr, motion});
    ASSERT_TRUE(s.isOk()) << s.toString();
  }

  // The validation layer's messages, one a line.
  std::string messages() const {
    std::ostringstream out;
    for (const std::string& m : host_.messages()) out << m << "\n";
    return out.str();
  }

  examples::HeadlessVulkan host_;
  std::string skip_reason_;  // Why startHost() returned false (empty when it failed).
};

// Pixels both images cover, and those whose motion is apart.
struct MotionApart {
  size_t covered = 0;           ///< Pixels both images cover.
  size_t apart = 0;             ///< Of those, the ones whose motions differ by more than 0.05 px.
  float largest_pixels = 0.0f;  ///< The longest of si::gl's motions there, in pixels.
};
// The host's image and motion (rows top to bottom, over VulkanRenderFixture::kBackground)
// against si::gl's MotionTarget's (readColor, readMotion: rows bottom to top). A pixel is a
// character's where a channel is more than 2 levels from the background (the two APIs may
// round the clear colour apart).
inline MotionApart motionApart(const std::vector<uint8_t>& image,
                               const std::vector<glm::vec2>& motion,
                               const std::vector<uint8_t>& gl_image,
                               const std::vector<glm::vec2>& gl_motion) {
  const glm::ivec3 clear(glm::round(glm::vec3(VulkanRenderFixture::kBackground) * 255.0f));
  const auto character_at = [&](const std::vector<uint8_t>& rgba, size_t i) {
    const glm::ivec3 c(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]);
    return glm::any(glm::greaterThan(glm::abs(c - clear), glm::ivec3(2)));
  };
  MotionApart a;
  for (size_t i = 0; i < motion.size() && i < gl_motion.size(); ++i) {
    const size_t g = (kSize - 1 - i / kSize) * kSize + i % kSize;  // The GL row's pixel.
    if (!character_at(image, i) || !character_at(gl_image, g)) continue;
    ++a.covered;
    const glm::vec2 pixels = (motion[i] - gl_motion[g]) * float(kSize);
    a.apart += std::max(std::abs(pixels.x), std::abs(pixels.y)) > 0.05f;
    a.largest_pixels = std::max(a.largest_pixels, glm::length(gl_motion[g]) * float(kSize));
  }
  return a;
}

// Expects the host's motion (`image`, `motion`) to be si::gl's (`gl_image`, `gl_motion`,
// glMotion()) where both images cover more than 2,000 pixels: at most 1 in 200 of them more than
// 0.05 px apart, si::gl's longest motion there longer than `least_largest_pixels` (the scene
// moves). Prints the counts.
inline void expectMotionOfOpenGl(const std::vector<uint8_t>& image,
                                 const std::vector<glm::vec2>& motion,
                                 const std::vector<uint8_t>& gl_image,
                                 const std::vector<glm::vec2>& gl_motion,
                                 float least_largest_pixels) {
  const MotionApart apart = motionApart(image, motion, gl_image, gl_motion);
  std::printf("[ motion ] %zu covered pixels, %zu apart, the largest motion %.2f px\n",
              apart.covered, apart.apart, apart.largest_pixels);
  EXPECT_GT(apart.covered, 2000u);
  EXPECT_GT(apart.largest_pixels, least_largest_pixels) << "the characters move by pixels";
  EXPECT_LE(apart.apart, apart.covered / 200)
      << apart.apart << " of " << apart.covered << " covered pixels apart";
}

// Expects a depth-only draw's depth (`depth_only`) to be the shaded draw's (`depth`) over the
// covered pixels (more than 2000), all but half a percent within 1e-6.
inline void expectSameDepth(const std::vector<float>& depth, const std::vector<float>& depth_only) {
  size_t covered = 0, apart = 0;
  for (size_t i = 0; i < depth.size() && i < depth_only.size(); ++i) {
    covered += depth[i] < 1.0f;
    apart += std::abs(depth[i] - depth_only[i]) > 1e-6f;
  }
  EXPECT_GT(covered, 2000u);
  EXPECT_LE(apart, covered / 200) << apart << " of " << covered;
}

// The embedded character's crowd of the LOD rows (populateLodCrowd).
inline void lodCrowd(CrowdManager* crowd) {
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = uint32_t(character().mesh.sub_meshes.size());
  cd.lod_count = uint32_t(character().mesh.maxLodCount());
  ASSERT_TRUE(crowd->init(cd).isOk());
  populateLodCrowd(crowd);
}

}  // namespace si::test

// Starts the host in a test body: skips the test (or fails it under SI_REQUIRE_VULKAN=1) when the
// machine has no Vulkan 1.3 device.
#define SI_START_VULKAN_HOST()                                 \
  do {                                                         \
    if (!startHost()) {                                        \
      if (!skip_reason_.empty()) GTEST_SKIP() << skip_reason_; \
      return;                                                  \
    }                                                          \
  } while (false)
