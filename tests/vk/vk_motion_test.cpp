// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Motion vectors on the Vulkan back-end (issue "The crowd in a Vulkan engine"): a crowd whose
// clips crossfade, cut and change speed while the camera moves draws, into colour attachment 1
// (RendererDesc::motion_format), the motion si::Renderer's vertex-shader path writes into its
// MotionTarget for the same two updates, pixel for pixel within a hundredth of a pixel's
// half-float rounding; on the GPU-driven path what si::gl's drawCrowdGpuCulled writes; a view
// without previous records is refused by name.
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
  // 16 characters of distinct clips, times and speeds (their handles into `handles`).
  static void sixteenCharacters(CrowdManager* crowd, bool previous_records,
                                std::vector<InstanceHandle>* handles) {
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = uint32_t(character().mesh.sub_meshes.size());
    cd.lod_count = 1;
    cd.previous_records = previous_records;
    ASSERT_TRUE(crowd->init(cd).isOk());
    const uint32_t clips = uint32_t(palette().clips.size());
    for (int k = 0; k < 16; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k % 4 - 1.5) * 1.3, 0.0, -3.0 - 1.6 * (k / 4));
      d.variation_mask = 1u | (uint32_t(k) << 1);
      d.clip = uint32_t(k) % clips;
      d.time_seconds = 0.13 * k;
      d.speed = 1.0f + 0.1f * float(k % 3);
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
      handles->push_back(h);
    }
  }
  // Crossfades, a cut and a speed change.
  static void changeClips(CrowdManager* crowd, const std::vector<InstanceHandle>& handles) {
    const uint32_t clips = uint32_t(palette().clips.size());
    for (size_t k = 0; k < handles.size(); k += 3)
      ASSERT_TRUE(crowd->crossfade(handles[k], (uint32_t(k) + 1) % clips, 0.4).isOk());
    ASSERT_TRUE(crowd->play(handles[0], 0, 0.5, 1.0f).isOk());
    ASSERT_TRUE(crowd->play(handles[2], 2 % clips, 0.2, 2.5f).isOk());
  }
  // sixteenCharacters() updated for frame 0; then changeClips() and the update of frame 2 (the
  // camera moved and turned).
  static void twoUpdates(CrowdManager* crowd, bool previous_records) {
    std::vector<InstanceHandle> handles;
    ASSERT_NO_FATAL_FAILURE(sixteenCharacters(crowd, previous_records, &handles));
    ASSERT_TRUE(crowd->update(0.05, camera(0)).isOk());
    ASSERT_NO_FATAL_FAILURE(changeClips(crowd, handles));
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

// The GPU-driven path (RendererDesc::gpu_driven with motion_format): the same crowd's two frames
// of passes and draws, the second after crossfades, a cut and a speed change with the camera
// moved and turned, write the motion si::gl's drawCrowdGpuCulled writes for the same two frames
// (each instance's previous record is what the view drew of it the frame before), pre-skinned in
// compute (the previous positions' ring) and skinned in the vertex stage (no ring).
TEST_P(VulkanMotionTest, TheGpuDrivenPathsMotionIsWhatOpenGlWrites) {
  SI_START_VULKAN_HOST();
  for (const bool pre_skinned : {true, false}) {
    SCOPED_TRACE(pre_skinned ? "pre-skinned" : "skinned in the vertex stage");
    CrowdManager crowd;
    std::vector<InstanceHandle> handles;
    ASSERT_NO_FATAL_FAILURE(sixteenCharacters(&crowd, false, &handles));
    // si::gl's GPU-driven path into a MotionTarget, and si::vk's, drawing each frame in turn.
    RendererDesc gd;
    gd.motion_vectors = true;
    Renderer gl;
    CharacterId gl_id;
    ASSERT_NO_FATAL_FAILURE(startGl(gd, &gl, &gl_id));
    MotionTarget target;
    ASSERT_TRUE(target.create(kSize, kSize).isOk());
    vk::Renderer r;
    vk::RendererDesc rd;
    rd.motion_format = examples::HeadlessVulkan::kMotionFormat;
    rd.gpu_driven = true;
    if (!pre_skinned) rd.gpu_driven_ring_bytes = 0;
    vk::CharacterId id;
    ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &r, &id));
    std::vector<uint8_t> gl_image, image;
    std::vector<glm::vec2> gl_motion, motion;
    for (uint32_t f = 0; f < 2; ++f) {
      if (f == 1) {
        ASSERT_NO_FATAL_FAILURE(changeClips(&crowd, handles));
      }
      ASSERT_TRUE(crowd.advance(f == 0 ? 0.05 : 1.0 / 30.0).isOk());
      ASSERT_NO_FATAL_FAILURE(drivenMotionFrame(gl, gl_id, target, r, id, f, crowd, camera(2 * f),
                                                pre_skinned, &gl_image, &gl_motion, &image,
                                                &motion));
    }
    expectMotionOfOpenGl(image, motion, gl_image, gl_motion, 2.0f);
    r.shutdown();
    gl.shutdown();
  }
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// Motion vectors with occlusion culling (GpuCulling::kOcclusion, both phases drawing into the
// colour and motion attachments): the wall crowd seen by a camera that moves, then steps aside
// past the wall's end, three frames, the last one's motion what si::gl's drawCrowdGpuCulled
// writes with gpu_occlusion_culling (each phase's instances take their previous records as one
// pass does; the characters that come into view are the second phase's).
TEST_P(VulkanMotionTest, TheGpuDrivenMotionWithOcclusionCullingIsWhatOpenGlWrites) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  makeCoarseCrowd(&crowd);
  populateWallCrowd(&crowd);
  // The last frame's camera steps aside past the wall's end: much of the crowd behind it comes
  // into view at once, drawn by the second phase.
  const auto cam = [](int f) {
    const glm::dvec3 eye =
        f < 2 ? glm::dvec3(0.1 * f, 1.0, 2.0 - 0.1 * f) : glm::dvec3(6.5, 1.0, 1.5);
    return Camera::lookAt(eye, {0.2 * f, 1.0, -40.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f, 500.0f);
  };
  RendererDesc gd;
  gd.motion_vectors = true;
  gd.gpu_occlusion_culling = true;
  Renderer gl;
  CharacterId gl_id;
  ASSERT_NO_FATAL_FAILURE(startGl(gd, &gl, &gl_id));
  MotionTarget target;
  ASSERT_TRUE(target.create(kSize, kSize).isOk());
  vk::Renderer r;
  vk::RendererDesc rd;
  rd.motion_format = examples::HeadlessVulkan::kMotionFormat;
  rd.gpu_driven = true;
  vk::CharacterId id;
  ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &r, &id));
  std::vector<uint8_t> gl_image, image;
  std::vector<glm::vec2> gl_motion, motion;
  const vk::DrawTarget area{{kSize, kSize}};
  for (int f = 0; f < 3; ++f) {
    ASSERT_TRUE(crowd.advance(f == 0 ? 0.0 : 1.0 / 30.0).isOk());
    target.clear(kBackground);
    const Status drawn = gl.drawCrowdGpuCulled(gl_id, crowd.view(), cam(f), nullptr);
    target.restore();
    ASSERT_TRUE(drawn.isOk()) << drawn.toString();
    ASSERT_TRUE(target.readMotion(&gl_motion).isOk());
    ASSERT_TRUE(target.readColor(&gl_image).isOk());
    examples::HeadlessVulkan::Frame frame;
    frame.clear_color = kBackground;
    frame.motion = true;
    frame.before = [&](VkCommandBuffer cmd) {
      const Status begun = r.beginFrame(uint32_t(f) % 2);
      return begun.isOk() ? r.recordGpuDrivenPasses(cmd, id, crowd.view(), cam(f), nullptr,
                                                    vk::GpuCulling::kOcclusion)
                          : begun;
    };
    const auto draw = [&](VkCommandBuffer cmd) {
      return r.recordGpuDrivenDraw(cmd, area, id, crowd.view());
    };
    frame.between = [&](VkCommandBuffer cmd, VkImageView depth) {
      vk::DepthSource source;
      source.view = depth;
      source.extent = area.extent;
      return r.recordGpuDrivenOcclusion(cmd, id, crowd.view(), source);
    };
    frame.after = draw;
    const Status s = host_.render(frame, draw, {&image, nullptr, &motion});
    ASSERT_TRUE(s.isOk()) << s.toString();
  }
  expectMotionOfOpenGl(image, motion, gl_image, gl_motion, 0.5f);
  r.shutdown();
  gl.shutdown();
  EXPECT_TRUE(host_.messages().empty()) << messages();
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
