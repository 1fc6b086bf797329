// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Layered animation on the Vulkan back-end (issue "The crowd in a Vulkan engine"): a crowd whose
// walkers wave an arm (an overlay on the right arm's mask, fading in for some) draws what
// si::Renderer's vertex-shader path draws, shaded and depth only; the overlay shows; its motion
// vectors follow the overlay as si::gl's do; on the GPU-driven path, pre-skinned and skinned in
// the vertex stage, what si::gl's drawCrowdGpuCulled draws and writes, the overlays' changes
// uploaded, and 2D blends too (through the layer compose pass); on the instanced path a 2D blend
// (whose third and fourth clips need the compose pass) is refused by name.
#include <glad/gl.h>

#include <functional>

#include "render/layered_scenes.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/gpu_crowd_state.h"
#include "vk/vk_render_fixture.h"

namespace si {
namespace {

using namespace test;

class VulkanLayersTest : public VulkanRenderFixture {
 protected:
  static Camera closeView(int f = 0) { return wavingView(f); }
  // 12 walkers; two thirds wave on the arm mask (at once, or fading in over 1 s), updated at
  // 0.5 s; with `previous_records`, updated again 1/30 s later with the camera moved.
  void populate(CrowdManager* crowd, bool previous_records) {
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = uint32_t(character().mesh.sub_meshes.size());
    cd.lod_count = 1;
    cd.previous_records = previous_records;
    ASSERT_TRUE(crowd->init(cd).isOk());
    ASSERT_NO_FATAL_FAILURE(populateWavingCrowd(crowd, &handles_));
    ASSERT_TRUE(crowd->update(0.5, closeView()).isOk());
    if (previous_records) {
      ASSERT_TRUE(crowd->update(1.0 / 30.0, closeView(1)).isOk());
    }
  }
  // `crowd` drawn by a fresh vk::Renderer (`rd`), shaded or depth only: the image or depth.
  void drawVulkan(const vk::RendererDesc& rd, const CrowdManager& crowd, const Camera& camera,
                  vk::DrawMode mode, std::vector<uint8_t>* image, std::vector<float>* depth,
                  std::vector<glm::vec2>* motion = nullptr) {
    vk::Renderer r;
    vk::CharacterId id;
    ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &r, &id));
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
    vk::DrawTarget target{{kSize, kSize}};
    target.mode = mode;
    examples::HeadlessVulkan::Frame frame;
    frame.clear_color = kBackground;
    frame.color = mode == vk::DrawMode::kShaded;
    frame.motion = motion != nullptr;
    const Status s =
        host_.render(frame,
                     [&](VkCommandBuffer cmd) {
                       const Status begun = r.beginFrame(0);
                       if (!begun.isOk()) return begun;
                       return r.recordDraw(cmd, target, id, crowd.view(), batcher, camera);
                     },
                     {image, depth, motion});
    ASSERT_TRUE(s.isOk()) << s.toString();
  }
  // si::gl's GPU-driven image of `crowd` with `camera` (pre-skinned, or in the vertex stage), over
  // kBackground, read from the default framebuffer.
  void glDriven(Renderer* gl, CharacterId id, const CrowdManager& crowd, const Camera& camera,
                bool pre_skinned, std::vector<uint8_t>* image) {
    gl->clear(kBackground);
    const Status drawn = gl->drawCrowdGpuCulled(
        id, crowd.view(), camera, nullptr, pre_skinned ? DrawMode::kDefault : DrawMode::kSkinned);
    ASSERT_TRUE(drawn.isOk()) << drawn.toString();
    ASSERT_TRUE(context_->readPixels(image).isOk());
  }
  // One GPU-driven frame of `crowd` by `r` (character `id`) in frame slot `slot`: its passes
  // with `camera`, then its draw in `mode`; the image and depth read back (each may be null),
  // what the passes uploaded into `stats` (may be null).
  void vkDriven(vk::Renderer* r, vk::CharacterId id, uint32_t slot, const CrowdManager& crowd,
                const Camera& camera, vk::DrawMode mode, std::vector<uint8_t>* image,
                std::vector<float>* depth, vk::PassStats* stats = nullptr) {
    examples::HeadlessVulkan::Frame frame;
    frame.clear_color = kBackground;
    frame.color = mode == vk::DrawMode::kShaded;
    frame.before = [&](VkCommandBuffer cmd) {
      const Status begun = r->beginFrame(slot);
      return begun.isOk() ? r->recordGpuDrivenPasses(cmd, id, crowd.view(), camera, stats) : begun;
    };
    vk::DrawTarget target{{kSize, kSize}};
    target.mode = mode;
    const Status s = host_.render(
        frame,
        [&](VkCommandBuffer cmd) { return r->recordGpuDrivenDraw(cmd, target, id, crowd.view()); },
        {image, depth});
    ASSERT_TRUE(s.isOk()) << s.toString();
  }
  // `count` instances in two rows playing a 2D blend of idle, walk, run and wave on a full-body
  // mask, each at its own point of the grid, updated at 0.5 s.
  void blendingCrowd(CrowdManager* crowd, int count) {
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = uint32_t(character().mesh.sub_meshes.size());
    cd.lod_count = 1;
    ASSERT_TRUE(crowd->init(cd).isOk());
    LayerMask body;
    ASSERT_TRUE(buildFullBodyMask(character().skeleton, palette(), "body", &body).isOk());
    uint32_t id = 0;
    ASSERT_TRUE(crowd->addLayerMask(body, &id).isOk());
    ASSERT_TRUE(crowd->addBlendSpace(idleWalkRunWaveGrid(id), &id).isOk());
    for (int k = 0; k < count; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k % 4 - 1.5) * 1.2, 0.0, -3.0 - 1.5 * (k / 4));
      d.time_seconds = 0.17 * k;
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
      const glm::vec2 at(float(k % 4) / 3.0f, k < 4 ? 0.25f : 0.8f);
      ASSERT_TRUE(crowd->playBlend(h, id, at, 0.0, 0.2).isOk());
    }
    ASSERT_TRUE(crowd->update(0.5, closeView()).isOk());
  }
  // Two GPU-driven frames of a crowd `make` fills (a fresh one each time), pre-skinned and in the
  // vertex stage, the second 1/30 s on with the camera moved: the colour and the motion that
  // si::gl's drawCrowdGpuCulled writes for the same frames (MotionTarget's rows run bottom to
  // top: the colour is compared through the motion check).
  void expectDrivenMotionOfOpenGl(const std::function<void(CrowdManager*)>& make) {
    RendererDesc gd;
    gd.motion_vectors = true;
    Renderer gl;
    CharacterId gl_id;
    ASSERT_NO_FATAL_FAILURE(startGl(gd, &gl, &gl_id));
    for (const bool pre_skinned : {true, false}) {
      SCOPED_TRACE(pre_skinned ? "pre-skinned" : "skinned in the vertex stage");
      CrowdManager crowd;
      ASSERT_NO_FATAL_FAILURE(make(&crowd));
      vk::RendererDesc rd;
      rd.gpu_driven = true;
      rd.motion_format = examples::HeadlessVulkan::kMotionFormat;
      if (!pre_skinned) rd.gpu_driven_ring_bytes = 0;
      vk::Renderer r;
      vk::CharacterId id;
      ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &r, &id));
      MotionTarget target;
      ASSERT_TRUE(target.create(kSize, kSize).isOk());
      std::vector<uint8_t> gl_image, image;
      std::vector<glm::vec2> gl_motion, motion;
      for (uint32_t f = 0; f < 2; ++f) {
        if (f == 1) {
          ASSERT_TRUE(crowd.advance(1.0 / 30.0).isOk());
        }
        ASSERT_NO_FATAL_FAILURE(drivenMotionFrame(gl, gl_id, target, r, id, f, crowd,
                                                  closeView(int(f)), pre_skinned, &gl_image,
                                                  &gl_motion, &image, &motion));
      }
      expectMotionOfOpenGl(image, motion, gl_image, gl_motion, 1.0f);
      r.shutdown();
    }
    gl.shutdown();
  }
  std::vector<InstanceHandle> handles_;
};

TEST_P(VulkanLayersTest, OverlaysDrawWhatOpenGlDraws) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  ASSERT_NO_FATAL_FAILURE(populate(&crowd, false));
  ASSERT_EQ(crowd.view().layerRecords().size(), crowd.view().records().size());
  // si::gl's image (its vertex-shader path composes the layers in a compute pass) and depth.
  Renderer gl;
  CharacterId gl_id;
  ASSERT_NO_FATAL_FAILURE(startGl(RendererDesc(), &gl, &gl_id));
  InstanceBatcher gl_batcher;
  ASSERT_TRUE(gl_batcher.init(gl.batchLimits()).isOk());
  const auto gl_draw = [&](std::vector<uint8_t>* image) {
    gl.clear(kBackground);
    const Status drawn = gl.drawCrowd(gl_id, crowd.view(), gl_batcher, closeView(), nullptr);
    ASSERT_TRUE(drawn.isOk()) << drawn.toString();
    ASSERT_TRUE(context_->readPixels(image).isOk());
  };
  std::vector<uint8_t> gl_image, vk_image;
  ASSERT_NO_FATAL_FAILURE(gl_draw(&gl_image));
  std::vector<float> depth, depth_only;
  ASSERT_NO_FATAL_FAILURE(
      drawVulkan({}, crowd, closeView(), vk::DrawMode::kShaded, &vk_image, &depth));
  ASSERT_NO_FATAL_FAILURE(
      drawVulkan({}, crowd, closeView(), vk::DrawMode::kDepthOnly, nullptr, &depth_only));
  const Diff diff = compare(vk_image, gl_image, nullptr);
  EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
  // The depth-only draw puts the overlaid arms where the shaded one does.
  size_t covered = 0, apart = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    covered += depth[i] < 1.0f;
    apart += std::abs(depth[i] - depth_only[i]) > 1e-6f;
  }
  EXPECT_GT(covered, 2000u);
  EXPECT_LE(apart, covered / 200) << apart << " of " << covered;
  // The overlay shows: stopped at once, the arms are elsewhere.
  for (InstanceHandle h : handles_) ASSERT_TRUE(crowd.stopOverlay(h, 0.0).isOk());
  ASSERT_TRUE(crowd.update(0.0, closeView()).isOk());
  std::vector<uint8_t> gl_plain;
  ASSERT_NO_FATAL_FAILURE(gl_draw(&gl_plain));
  EXPECT_GT(compare(gl_plain, gl_image, nullptr).share, 0.01);
  gl.shutdown();
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// Motion vectors of overlays: the previous position is skinned with the previous layer record.
TEST_P(VulkanLayersTest, MotionVectorsFollowTheOverlayAsOpenGlsDo) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  ASSERT_NO_FATAL_FAILURE(populate(&crowd, true));
  std::vector<glm::vec2> gl_motion;
  std::vector<uint8_t> gl_image;
  ASSERT_NO_FATAL_FAILURE(glMotion(crowd, closeView(1), &gl_image, &gl_motion));
  vk::RendererDesc rd;
  rd.motion_format = examples::HeadlessVulkan::kMotionFormat;
  std::vector<uint8_t> image;
  std::vector<glm::vec2> motion;
  ASSERT_NO_FATAL_FAILURE(
      drawVulkan(rd, crowd, closeView(1), vk::DrawMode::kShaded, &image, nullptr, &motion));
  expectMotionOfOpenGl(image, motion, gl_image, gl_motion, 1.0f);
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// The GPU-driven path: the cull pass writes each visible instance's layer record, the
// pre-skinning pass or the vertex stage composes the overlay on its mask, as si::gl's
// drawCrowdGpuCulled does (which composes the masked rows in a pass of their own first).
TEST_P(VulkanLayersTest, TheGpuDrivenPathDrawsOverlaysAsOpenGlsDoes) {
  SI_START_VULKAN_HOST();
  Renderer gl;
  CharacterId gl_id;
  ASSERT_NO_FATAL_FAILURE(startGl(RendererDesc(), &gl, &gl_id));
  for (const bool pre_skinned : {true, false}) {
    SCOPED_TRACE(pre_skinned ? "pre-skinned" : "skinned in the vertex stage");
    CrowdManager crowd;
    handles_.clear();
    ASSERT_NO_FATAL_FAILURE(populate(&crowd, false));
    vk::RendererDesc rd;
    rd.gpu_driven = true;
    if (!pre_skinned) rd.gpu_driven_ring_bytes = 0;
    vk::Renderer r;
    vk::CharacterId id;
    ASSERT_NO_FATAL_FAILURE(startRenderer(rd, &r, &id));
    std::vector<uint8_t> gl_image, image;
    std::vector<float> depth, depth_only;
    ASSERT_NO_FATAL_FAILURE(glDriven(&gl, gl_id, crowd, closeView(), pre_skinned, &gl_image));
    ASSERT_NO_FATAL_FAILURE(
        vkDriven(&r, id, 0, crowd, closeView(), vk::DrawMode::kShaded, &image, &depth));
    Diff diff = compare(image, gl_image, nullptr);
    EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
    vk::GpuDrivenCounts counts;
    ASSERT_TRUE(r.readGpuDrivenCounts(id, crowd.view(), &counts).isOk());
    EXPECT_EQ(counts.pre_skinned_vertices > 0, pre_skinned);
    ASSERT_NO_FATAL_FAILURE(
        vkDriven(&r, id, 1, crowd, closeView(), vk::DrawMode::kDepthOnly, nullptr, &depth_only));
    expectSameDepth(depth, depth_only);
    // Two overlays of the front row stopped at once: their changed state reaches the GPU (a
    // copy per changed run, not the whole crowd), the two arms go elsewhere.
    for (int k = 0; k < 2; ++k) ASSERT_TRUE(crowd.stopOverlay(handles_[k], 0.0).isOk());
    ASSERT_TRUE(crowd.advance(0.0).isOk());
    std::vector<uint8_t> gl_plain, plain;
    ASSERT_NO_FATAL_FAILURE(glDriven(&gl, gl_id, crowd, closeView(), pre_skinned, &gl_plain));
    vk::PassStats uploaded;
    ASSERT_NO_FATAL_FAILURE(
        vkDriven(&r, id, 0, crowd, closeView(), vk::DrawMode::kShaded, &plain, nullptr, &uploaded));
    EXPECT_FALSE(uploaded.whole_upload);
    EXPECT_EQ(uploaded.state_bytes_uploaded,
              2 * (sizeof(GpuInstanceState) + sizeof(GpuOverlayState)));
    diff = compare(plain, gl_plain, nullptr);
    EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
    const double moved = compare(plain, image, nullptr).share;
    std::printf("[ layers ] %.2f %% of pixels moved with two overlays stopped\n", 100.0 * moved);
    EXPECT_GT(moved, 0.005);
    r.shutdown();
  }
  gl.shutdown();
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// Motion vectors of overlays on the GPU-driven path: two frames, the previous position skinned
// with the previous layer record the view drew, as si::gl's drawCrowdGpuCulled writes.
TEST_P(VulkanLayersTest, TheGpuDrivenMotionFollowsTheOverlayAsOpenGlsDoes) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(expectDrivenMotionOfOpenGl([&](CrowdManager* crowd) {
    handles_.clear();
    populate(crowd, false);
  }));
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// 2D blends on the GPU-driven path: the cull pass writes each visible instance's two extra
// layer records after the layer records, the layer compose pass composes its masked rows from
// the four clips, and the skinning reads them, as si::gl's drawCrowdGpuCulled does; two frames,
// the second's image and motion vectors (the previous rows composed from the previous records)
// against si::gl's, pre-skinned and in the vertex stage.
TEST_P(VulkanLayersTest, TheGpuDrivenPathDrawsTwoDimensionalBlendsAsOpenGlsDoes) {
  SI_START_VULKAN_HOST();
  ASSERT_NO_FATAL_FAILURE(expectDrivenMotionOfOpenGl([&](CrowdManager* crowd) {
    blendingCrowd(crowd, 8);
    ASSERT_TRUE(CrowdExport(*crowd).writesExtraLayers());
  }));
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

TEST_P(VulkanLayersTest, ABlendsThirdAndFourthClipsAreRefusedByName) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  ASSERT_NO_FATAL_FAILURE(blendingCrowd(&crowd, 1));
  ASSERT_TRUE(crowd.update(0.1, closeView()).isOk());
  ASSERT_FALSE(crowd.view().extraLayerRecords().empty());
  vk::Renderer r;
  vk::CharacterId vk_id;
  ASSERT_NO_FATAL_FAILURE(startRenderer({}, &r, &vk_id));
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  ASSERT_TRUE(r.beginFrame(0).isOk());
  const Status s = r.recordDraw(VK_NULL_HANDLE, vk::DrawTarget{{kSize, kSize}}, vk_id, crowd.view(),
                                batcher, closeView());
  EXPECT_EQ(s.code(), StatusCode::kUnsupported);
  EXPECT_NE(s.message().find("2D blends"), std::string::npos) << s.toString();
}

INSTANTIATE_TEST_SUITE_P(Backends, VulkanLayersTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
