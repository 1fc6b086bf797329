// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Impostors on the Vulkan back-end (issue "The crowd in a Vulkan engine", item 3): the atlas
// vk::Renderer::buildImpostor captures in the host's recordUploads submission, drawn by the
// GPU-driven path's impostor quads pass and impostor draw, gives si::gl's image of the same
// crowd (its atlas captured by si::Renderer::buildImpostor) within the golden tolerance, on
// lavapipe with the validation layer on and silent; a depth-only view writes the shaded draw's
// depth; what is missing or not built is refused by name.
#include <glad/gl.h>

#include <cmath>
#include <cstdio>

#include "render/impostor_fixture.h"
#include "si/crowd/crowd_manager.h"
#include "vk/vk_render_fixture.h"

namespace si {
namespace {

using namespace test;

// flatCamera() over the tests' images (Camera::viewport_height_pixels: the impostor quads pass
// leaves out the quads that cover none of its pixel centres).
Camera camera() {
  Camera c = flatCamera();
  c.viewport_height_pixels = float(kSize);
  return c;
}

class VulkanImpostorTest : public VulkanRenderFixture {
 protected:
  // A GPU-driven renderer of impostorCharacter() on host_ (motion vectors in `motion`), with
  // its atlas built from smallImpostor() (unless `atlas` is false) and its uploads submitted.
  void start(vk::Renderer* r, vk::CharacterId* id, bool atlas = true,
             VkFormat motion = VK_FORMAT_UNDEFINED, ImpostorInfo* info = nullptr,
             const Character& character = impostorCharacter(),
             const ImpostorDesc& desc = smallImpostor()) {
    vk::RendererDesc rd;
    rd.gpu_driven = true;
    rd.motion_format = motion;
    rd.physical_device = host_.physicalDevice();
    rd.device = host_.device();
    Status s = r->init(rd);
    ASSERT_TRUE(s.isOk()) << s.toString();
    ASSERT_TRUE(r->addCharacter(character, palette(), id).isOk());
    if (atlas) {
      s = r->buildImpostor(*id, desc, info);
      ASSERT_TRUE(s.isOk()) << s.toString();
    }
    s = host_.submit([&](VkCommandBuffer cmd) { return r->recordUploads(cmd); });
    ASSERT_TRUE(s.isOk()) << s.toString();
    r->uploadsComplete();
  }

  // si::gl's GPU-driven image of `crowd` (a crowd of `character`), its atlas built from `desc`
  // (both back-ends capture it 2 x 2 by default and resolve it by the same pass), and its counts.
  void glImage(const Character& character, const CrowdManager& crowd, std::vector<uint8_t>* image,
               DrawStats* stats, const ImpostorDesc& desc = smallImpostor()) {
    Renderer gl;
    RendererDesc rd;
    rd.measure_gpu_time = true;  // The counts read back.
    ASSERT_TRUE(gl.init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(gl.addCharacter(character, palette(), &id).isOk());
    ImpostorInfo info;
    ASSERT_TRUE(gl.buildImpostor(id, desc, &info).isOk());
    EXPECT_EQ(info.capture_supersample, 2u);
    gl.clear(kBackground);
    const Status s = drawOnPath(gl, PathKind::kGpuDriven, crowd, camera(), stats);
    ASSERT_TRUE(s.isOk()) << s.toString();
    ASSERT_TRUE(context_->readPixels(image).isOk());
  }

  // One frame: `view`'s passes with `camera`, then its draw in `mode`; colour and depth read.
  Status frame(vk::Renderer& r, vk::CharacterId id, const CrowdView& view, const Camera& camera,
               vk::DrawMode mode, std::vector<uint8_t>* image, std::vector<float>* depth) {
    examples::HeadlessVulkan::Frame f;
    f.clear_color = kBackground;
    f.color = mode == vk::DrawMode::kShaded;
    f.before = [&](VkCommandBuffer cmd) {
      Status s = r.beginFrame(0);
      if (s.isOk()) s = r.recordGpuDrivenPasses(cmd, id, view, camera);
      return s;
    };
    vk::DrawTarget target{{kSize, kSize}};
    target.mode = mode;
    return host_.render(f,
                        [&](VkCommandBuffer cmd) {
                          vk::DrawStats stats;
                          const Status s = r.recordGpuDrivenDraw(cmd, target, id, view, &stats);
                          // The pre-skinned meshes', the others' and the impostors'.
                          EXPECT_EQ(stats.draw_calls, 3u);
                          return s;
                        },
                        {image, depth});
  }
};

// Near rows of meshes and far rows of impostors in front of camera(), every clip at several
// times and turns; the impostor line 20 units out.
void mixedCrowd(CrowdManager* crowd) {
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = 4;
  cd.lod_count = impostorLevels();
  cd.character_radius = 1.0f;
  cd.lod_distances_radii = linesTo(20.0f);
  cd.max_distance_radii = -1.0f;
  cd.impostor_lod = impostorLevels() - 1;
  ASSERT_TRUE(crowd->init(cd).isOk());
  const double rows[] = {-6.0, -14.0, -24.0, -36.0, -50.0};
  for (int row = 0; row < 5; ++row)
    for (int k = 0; k < 9; ++k)
      ASSERT_NO_FATAL_FAILURE(addHeld(crowd, {(k - 4) * (2.0 + row * 1.5), -1.5, rows[row]},
                                      0.7f * float(k + row), uint32_t(k + row), 0.11 * double(k)));
  // Far rows of small characters: cells of about a third of a pixel, whose quads mostly cover no
  // pixel centre, and of about one pixel, whose whole cells would cover one more often than the
  // part of the cell the character covers.
  for (int k = 0; k < 48; ++k) {
    InstanceDesc inst;
    inst.position = glm::dvec3((k % 24 - 12) * 7.0 + 0.37 * k, 3.0 * (k / 24), -450.0);
    inst.rotation = glm::angleAxis(0.9f * float(k), glm::vec3(0, 1, 0));
    inst.clip = uint32_t(k) % uint32_t(palette().clips.size());
    inst.scale = k < 24 ? 0.2f : 0.6f;
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(inst, &h).isOk());
  }
  ASSERT_TRUE(crowd->advance(0.3).isOk());
  ASSERT_TRUE(crowd->update(0.0, camera()).isOk());
}

TEST_P(VulkanImpostorTest, TheGpuDrivenPathsImpostorsGiveOpenGlsImage) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  ASSERT_NO_FATAL_FAILURE(mixedCrowd(&crowd));
  const uint32_t impostors = crowd.view().stats().per_lod[impostorLevels() - 1];
  EXPECT_GE(impostors, 9u);
  EXPECT_LT(impostors, crowd.size());
  EXPECT_GE(crowd.size() - impostors, 9u);
  std::vector<uint8_t> gl_image;
  DrawStats gl_stats;
  ASSERT_NO_FATAL_FAILURE(glImage(impostorCharacter(), crowd, &gl_image, &gl_stats));
  vk::Renderer r;
  vk::CharacterId id;
  ImpostorInfo info;
  ASSERT_NO_FATAL_FAILURE(start(&r, &id, true, VK_FORMAT_UNDEFINED, &info));
  EXPECT_TRUE(r.hasImpostor(id));
  EXPECT_EQ(info.views, 16u);
  EXPECT_EQ(info.cells, info.views * info.frames);
  EXPECT_EQ(info.capture_supersample, 2u) << "the default: a supersampled capture, resolved";
  std::vector<uint8_t> image;
  std::vector<float> depth, depth_only;
  Status s = frame(r, id, crowd.view(), camera(), vk::DrawMode::kShaded, &image, &depth);
  ASSERT_TRUE(s.isOk()) << s.toString();
  const Diff diff = compare(image, gl_image, nullptr);
  std::printf(
      "[ impostors ] %u of %u instances impostors; %.4f %% of pixels apart from si::gl's, "
      "max channel %d\n",
      impostors, crowd.size(), 100.0 * diff.share, diff.max_channel);
  EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
  if (diff.share > kMaxDifferingShare) {
    const std::string base = ::testing::TempDir() + "si_vk_impostors";
    EXPECT_TRUE(writePng(base + ".png", kSize, kSize, image).isOk());
    EXPECT_TRUE(writePng(base + "_gl.png", kSize, kSize, gl_image).isOk());
  }
  vk::GpuDrivenCounts counts;
  ASSERT_TRUE(r.readGpuDrivenCounts(id, crowd.view(), &counts).isOk());
  EXPECT_EQ(counts.visible, gl_stats.gpu_visible);
  // Both leave out the quads that cover no pixel centre of the camera's viewport, each quad cut
  // to its cell's covered rectangle (si::gl's read back from the atlas, si::vk's measured on the
  // GPU): the same quads.
  const uint64_t all_kept = gl_stats.triangles + 2 * uint64_t(gl_stats.impostors_left_out);
  std::printf("[ impostors ] triangles: si::gl %llu, si::vk %llu, every quad kept %llu\n",
              static_cast<unsigned long long>(gl_stats.triangles),
              static_cast<unsigned long long>(counts.triangles),
              static_cast<unsigned long long>(all_kept));
  EXPECT_GT(gl_stats.impostors_left_out, 0u) << "the far row's quads cover no pixel centre";
  EXPECT_EQ(counts.triangles, gl_stats.triangles) << "the same cells' covered rectangles";
  EXPECT_LT(counts.triangles, all_kept) << "quads that cover no pixel centre are left out";
  EXPECT_GT(counts.impostors_left_out, 0u);
  EXPECT_EQ(counts.instances + counts.impostors_left_out,
            gl_stats.instances + gl_stats.impostors_left_out);
  // A shadow view's impostors: the coverage test alone writes the shaded draw's depth.
  s = frame(r, id, crowd.view(), camera(), vk::DrawMode::kDepthOnly, nullptr, &depth_only);
  ASSERT_TRUE(s.isOk()) << s.toString();
  expectSameDepth(depth, depth_only);
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// impostorCharacter() with its parts in two materials of one colour: a matte one and a metallic
// one, so that the built-in material shades them apart.
const Character& twoMaterialCharacter() {
  static const Character c = [] {
    Character k = impostorCharacter();
    Material matte{"matte", glm::vec4(0.8f, 0.7f, 0.6f, 1.0f), -1, 0.0f, 1.0f};
    Material metal = matte;
    metal.name = "metal";
    metal.metallic_factor = 1.0f;
    metal.roughness_factor = 0.3f;
    k.materials = {matte, metal};
    for (size_t s = 0; s < k.mesh.sub_meshes.size(); ++s) k.mesh.sub_meshes[s].material = s % 2;
    return k;
  }();
  return c;
}

// Where a level-0 texel of the supersampled capture holds both materials, the resolve keeps one
// material's metallic and roughness (its second dispatch, after the mip chain), as si::gl's does:
// every impostor of a two-material crowd, some 60 pixels tall, gives si::gl's image.
TEST_P(VulkanImpostorTest, ATwoMaterialImpostorGivesOpenGlsImage) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  ASSERT_NO_FATAL_FAILURE(initEveryOneAt(true, &crowd));
  for (int k = 0; k < 12; ++k)
    ASSERT_NO_FATAL_FAILURE(addHeld(&crowd, {(k % 6 - 2.5) * 1.1, (k / 6) * 2.2 - 2.0, -6.0},
                                    0.6f * float(k), uint32_t(k), 0.13 * double(k)));
  ASSERT_TRUE(crowd.advance(0.3).isOk());
  ASSERT_TRUE(crowd.update(0.0, camera()).isOk());
  ASSERT_EQ(crowd.view().stats().per_lod[impostorLevels() - 1], crowd.size());
  std::vector<uint8_t> gl_image;
  DrawStats gl_stats;
  ASSERT_NO_FATAL_FAILURE(glImage(twoMaterialCharacter(), crowd, &gl_image, &gl_stats));
  vk::Renderer r;
  vk::CharacterId id;
  ImpostorInfo info;
  ASSERT_NO_FATAL_FAILURE(start(&r, &id, true, VK_FORMAT_UNDEFINED, &info, twoMaterialCharacter()));
  EXPECT_EQ(info.capture_supersample, 2u);
  EXPECT_FALSE(info.uniform_surface);
  std::vector<uint8_t> image;
  const Status s = frame(r, id, crowd.view(), camera(), vk::DrawMode::kShaded, &image, nullptr);
  ASSERT_TRUE(s.isOk()) << s.toString();
  const double drawn = compare(image, blankImage(image), nullptr).share;
  const Diff diff = compare(image, gl_image, nullptr);
  std::printf(
      "[ impostors ] two materials: %.1f %% of pixels drawn; %.4f %% apart from "
      "si::gl's, max channel %d\n",
      100.0 * drawn, 100.0 * diff.share, diff.max_channel);
  EXPECT_GT(drawn, 0.1);
  EXPECT_LE(diff.share, kMaxDifferingShare / 10) << "max channel difference " << diff.max_channel;
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// ImpostorDesc::lod_bias: impostors a few pixels tall read the levels si::gl's read (each
// atlas's own sampler), the image si::gl's; another bias draws another image.
TEST_P(VulkanImpostorTest, ALodBiasReadsTheLevelsOpenGlReads) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  ASSERT_NO_FATAL_FAILURE(initEveryOneAt(true, &crowd));
  for (int k = 0; k < 60; ++k)
    ASSERT_NO_FATAL_FAILURE(addHeld(&crowd, {(k % 12 - 5.5) * 3.0, (k / 12 - 2.0) * 3.0, -50.0},
                                    0.7f * float(k), uint32_t(k), 0.07 * double(k % 11)));
  ASSERT_TRUE(crowd.advance(0.2).isOk());
  ASSERT_TRUE(crowd.update(0.0, camera()).isOk());
  ImpostorDesc sharper = smallImpostor();
  sharper.lod_bias = -1.0f;
  std::vector<uint8_t> gl_image, gl_trilinear;
  DrawStats gl_stats;
  ASSERT_NO_FATAL_FAILURE(glImage(impostorCharacter(), crowd, &gl_image, &gl_stats, sharper));
  ASSERT_NO_FATAL_FAILURE(glImage(impostorCharacter(), crowd, &gl_trilinear, &gl_stats));
  vk::Renderer r;
  vk::CharacterId id;
  ASSERT_NO_FATAL_FAILURE(
      start(&r, &id, true, VK_FORMAT_UNDEFINED, nullptr, impostorCharacter(), sharper));
  std::vector<uint8_t> image;
  const Status s = frame(r, id, crowd.view(), camera(), vk::DrawMode::kShaded, &image, nullptr);
  ASSERT_TRUE(s.isOk()) << s.toString();
  const Diff diff = compare(image, gl_image, nullptr);
  const double apart = compare(gl_trilinear, gl_image, nullptr).share;
  std::printf(
      "[ impostors ] LOD bias -1: %.4f %% of pixels apart from si::gl's (bias 0 draws "
      "%.4f %% apart)\n",
      100.0 * diff.share, 100.0 * apart);
  EXPECT_GT(apart, 0.002) << "the bias reads other levels";
  EXPECT_LE(diff.share, kMaxDifferingShare / 10) << "max channel difference " << diff.max_channel;
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

TEST_P(VulkanImpostorTest, RefusalsAreNamed) {
  SI_START_VULKAN_HOST();
  CrowdManager crowd;
  ASSERT_NO_FATAL_FAILURE(mixedCrowd(&crowd));
  const auto refused = [](const Status& s, StatusCode code, const char* words) {
    EXPECT_EQ(s.code(), code) << s.toString();
    EXPECT_NE(s.message().find(words), std::string::npos) << s.message();
  };
  {
    // No atlas: the crowd's impostor level has nothing to draw with.
    vk::Renderer r;
    vk::CharacterId id;
    ASSERT_NO_FATAL_FAILURE(start(&r, &id, false));
    EXPECT_FALSE(r.hasImpostor(id));
    refused(frame(r, id, crowd.view(), camera(), vk::DrawMode::kShaded, nullptr, nullptr),
            StatusCode::kInvalidArgument, "no impostor atlas");
    // Bad descs, as si::Renderer refuses them, with the plan reported.
    ImpostorDesc bad = smallImpostor();
    bad.elevations_degrees = {30.0f, 0.0f};
    refused(r.buildImpostor(id, bad), StatusCode::kInvalidArgument, "elevations must increase");
    bad = smallImpostor();
    bad.max_bytes = 1024;
    ImpostorInfo info;
    refused(r.buildImpostor(id, bad, &info), StatusCode::kLimitExceeded, "max_bytes");
    EXPECT_GT(info.bytes, 1024u);
    bad = smallImpostor();
    bad.lod_bias = -3.0f;
    refused(r.buildImpostor(id, bad), StatusCode::kInvalidArgument, "lod_bias");
    bad = smallImpostor();
    bad.capture_supersample = 3;
    refused(r.buildImpostor(id, bad), StatusCode::kInvalidArgument, "1, 2 or 4");
    bad = smallImpostor();
    bad.cell_pixels = 1u << 20;
    refused(r.buildImpostor(id, bad), StatusCode::kLimitExceeded, "maxImageDimension2D");
    refused(r.buildImpostor(vk::CharacterId{7}, smallImpostor()), StatusCode::kInvalidArgument,
            "no character 7");
    EXPECT_FALSE(r.hasImpostor(id));
  }
  {
    // The instanced path draws no impostors yet.
    vk::Renderer r;
    vk::CharacterId id;
    ASSERT_NO_FATAL_FAILURE(start(&r, &id));
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
    examples::HeadlessVulkan::Frame f;
    const Status s = host_.render(f,
                                  [&](VkCommandBuffer cmd) {
                                    Status begun = r.beginFrame(0);
                                    if (!begun.isOk()) return begun;
                                    return r.recordDraw(cmd, vk::DrawTarget{{kSize, kSize}}, id,
                                                        crowd.view(), batcher, camera());
                                  },
                                  {});
    refused(s, StatusCode::kUnsupported, "does not draw impostors");
  }
  {
    // Only the GPU-driven path draws impostors.
    vk::Renderer r;
    vk::RendererDesc rd;
    rd.physical_device = host_.physicalDevice();
    rd.device = host_.device();
    ASSERT_TRUE(r.init(rd).isOk());
    vk::CharacterId id;
    ASSERT_TRUE(r.addCharacter(impostorCharacter(), palette(), &id).isOk());
    refused(r.buildImpostor(id, smallImpostor()), StatusCode::kUnsupported, "GPU-driven path");
  }
  {
    // Impostors draw no motion vectors, as on si::gl.
    vk::Renderer r;
    vk::CharacterId id;
    ASSERT_NO_FATAL_FAILURE(start(&r, &id, true, VK_FORMAT_R16G16_SFLOAT));
    refused(frame(r, id, crowd.view(), camera(), vk::DrawMode::kShaded, nullptr, nullptr),
            StatusCode::kUnsupported, "motion vectors");
  }
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

INSTANTIATE_TEST_SUITE_P(Backends, VulkanImpostorTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
