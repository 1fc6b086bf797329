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
#include "vk/vk_gpu_driven_fixture.h"

namespace si {
namespace {

using namespace test;

class VulkanGpuDrivenTest : public VulkanGpuDrivenFixture {};

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
  // si::gl's image of each view, once for the three rings.
  DrawStats gl_stats_of[2];
  const std::vector<uint8_t> gl_image_of[2] = {glImage(crowd, views[0].second, &gl_stats_of[0]),
                                               glImage(crowd, views[1].second, &gl_stats_of[1])};
  uint32_t slot = 0;
  for (const auto& [ring_name, ring_bytes] : rings)
    for (const auto& [name, camera] : views) {
      SCOPED_TRACE(name);
      SCOPED_TRACE(ring_name);
      if (&camera == &views[0].second) {
        ASSERT_NO_FATAL_FAILURE(start(ring_bytes));
      }
      const size_t v = &camera == &views[0].second ? 0 : 1;
      const DrawStats& gl_stats = gl_stats_of[v];
      const std::vector<uint8_t>& gl_image = gl_image_of[v];
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
