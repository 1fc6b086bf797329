// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Motion vectors on the Vulkan back-end (issue "The crowd in a Vulkan engine"): a crowd whose
// clips crossfade, cut and change speed while the camera moves draws, into colour attachment 1
// (RendererDesc::motion_format), the motion si::Renderer's vertex-shader path writes into its
// MotionTarget for the same two updates, pixel for pixel within a hundredth of a pixel's
// half-float rounding; a view without previous records is refused by name.
#include <glad/gl.h>

#include <algorithm>
#include <cmath>

#include "vk/vk_render_fixture.h"

namespace si {
namespace {

using namespace test;

class VulkanMotionTest : public VulkanRenderFixture {
 protected:
  static Camera camera(int f) {
    return Camera::lookAt({0.3 * f, 1.6, 2.5 - 0.2 * f}, {0.1 * f, 0.9, -5.0}, glm::vec3(0, 1, 0),
                          0.9f, 1.0f, 0.1f, 100.0f);
  }
  // 16 characters of distinct clips, times and speeds, updated for frame 0; then crossfades, a
  // cut and a speed change, and the update of frame 2 (the camera moved and turned).
  static void twoUpdates(CrowdManager* crowd, bool previous_records) {
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = uint32_t(character().mesh.sub_meshes.size());
    cd.lod_count = 1;
    cd.previous_records = previous_records;
    ASSERT_TRUE(crowd->init(cd).isOk());
    const uint32_t clips = uint32_t(palette().clips.size());
    std::vector<InstanceHandle> handles;
    for (int k = 0; k < 16; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k % 4 - 1.5) * 1.3, 0.0, -3.0 - 1.6 * (k / 4));
      d.variation_mask = 1u | (uint32_t(k) << 1);
      d.clip = uint32_t(k) % clips;
      d.time_seconds = 0.13 * k;
      d.speed = 1.0f + 0.1f * float(k % 3);
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
      handles.push_back(h);
    }
    ASSERT_TRUE(crowd->update(0.05, camera(0)).isOk());
    for (size_t k = 0; k < handles.size(); k += 3)
      ASSERT_TRUE(crowd->crossfade(handles[k], (uint32_t(k) + 1) % clips, 0.4).isOk());
    ASSERT_TRUE(crowd->play(handles[0], 0, 0.5, 1.0f).isOk());
    ASSERT_TRUE(crowd->play(handles[2], 2 % clips, 0.2, 2.5f).isOk());
    ASSERT_TRUE(crowd->update(1.0 / 30.0, camera(2)).isOk());
  }
};

TEST_P(VulkanMotionTest, TheMotionIsWhatOpenGlWrites) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  ASSERT_NO_FATAL_FAILURE(twoUpdates(&crowd, true));
  // si::gl's motion: the vertex-shader path into a MotionTarget (rows bottom to top).
  std::vector<glm::vec2> gl_motion;
  std::vector<uint8_t> gl_image;
  ASSERT_NO_FATAL_FAILURE(glMotion(crowd, camera(2), &gl_image, &gl_motion));
  vk::Renderer r;
  vk::RendererDesc rd;
  rd.motion_format = examples::HeadlessVulkan::kMotionFormat;
  vk::CharacterId id;
  ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &r, &id));
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  examples::HeadlessVulkan::Frame frame;
  frame.clear_color = kBackground;
  frame.motion = true;
  std::vector<uint8_t> image;
  std::vector<glm::vec2> motion;
  const Status s = host_.render(frame,
                                [&](VkCommandBuffer cmd) {
                                  const Status begun = r.beginFrame(0);
                                  if (!begun.isOk()) return begun;
                                  return r.recordDraw(cmd, vk::DrawTarget{{kSize, kSize}}, id,
                                                      crowd.view(), batcher, camera(2));
                                },
                                {&image, nullptr, &motion});
  ASSERT_TRUE(s.isOk()) << s.toString();
  expectMotionOfOpenGl(image, motion, gl_image, gl_motion, 2.0f);
  EXPECT_TRUE(host_.messages().empty()) << messages();
  r.shutdown();
}

TEST_P(VulkanMotionTest, AViewWithoutPreviousRecordsIsRefusedByName) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  ASSERT_NO_FATAL_FAILURE(twoUpdates(&crowd, false));
  vk::Renderer r;
  vk::RendererDesc rd;
  rd.motion_format = examples::HeadlessVulkan::kMotionFormat;
  vk::CharacterId id;
  ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &r, &id));
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  ASSERT_TRUE(r.beginFrame(0).isOk());
  const Status s = r.recordDraw(VK_NULL_HANDLE, vk::DrawTarget{{kSize, kSize}}, id, crowd.view(),
                                batcher, camera(2));
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("previous_records"), std::string::npos) << s.toString();
  rd.motion_format = VK_FORMAT_D32_SFLOAT;  // No colour attachment format.
  vk::Renderer depth_motion;
  rd.physical_device = host_.physicalDevice();
  rd.device = host_.device();
  EXPECT_EQ(depth_motion.init(rd).code(), StatusCode::kUnsupported);
  EXPECT_TRUE(host_.messages().empty()) << messages();
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, VulkanMotionTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
