// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Characters beyond the embedded one on the Vulkan back-end (issue "The crowd in a Vulkan
// engine"): a mesh that keeps 8 influences a vertex (tests/gltf/eight_influence_asset.h) and one
// with vertex colours and a second texture coordinate set (tests/gltf/pbr_asset.h) draw what
// si::Renderer's vertex-shader path draws of them, each in the program variant for its mesh;
// where the variant mattered (influences 5 to 8, the colours) is checked to show.
#include "gltf/eight_influence_asset.h"
#include "gltf/import_json.h"
#include "gltf/pbr_asset.h"
#include "render/morph_scenes.h"
#include "si/gltf/gltf_import.h"
#include "vk/vk_render_fixture.h"

namespace si {
namespace {

using namespace test;

class VulkanCharacterTest : public VulkanRenderFixture {
 protected:
  // `c` baked, a crowd of `count` instances of it in a row at times `first` + 0.3 k, tinted;
  // si::gl's and si::vk's images of it with `camera`.
  void drawBoth(const Character& c, int count, double first, const Camera& camera,
                std::vector<uint8_t>* gl_image, std::vector<uint8_t>* vk_image) {
    BakedPalette baked;
    BakeDesc bd;
    bd.rate_mode = RateMode::kFixed;
    bd.sample_rate_hz = 30.0f;
    ASSERT_TRUE(bakePalette(c, bd, &baked, nullptr).isOk());
    CrowdManager crowd;
    CrowdDesc cd;
    cd.palette = &baked;
    cd.sub_mesh_count = uint32_t(c.mesh.sub_meshes.size());
    cd.lod_count = 1;
    ASSERT_TRUE(crowd.init(cd).isOk());
    for (int k = 0; k < count; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3(-1.6 * (count - 1) / 2.0 + 1.6 * k, 0.0, 0.0);
      d.time_seconds = first + 0.3 * k;
      d.speed = 0.0f;
      d.color = glm::u8vec4(uint8_t(120 + 60 * k), 200, 160, 255);
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(d, &h).isOk());
    }
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    if (!gl_started_) {
      ASSERT_TRUE(gl_.init(info_, RendererDesc()).isOk());
      gl_started_ = true;
    }
    ASSERT_NO_FATAL_FAILURE(glImage(c, baked, crowd, camera, gl_image));
    *vk_image = vulkanImage(c, baked, crowd, camera);
  }
  // `crowd`'s last selection of `c` drawn by si::gl's vertex-shader path (gl_, one renderer for
  // the test's characters: its programs are compiled once) over kBackground: the image.
  void glImage(const Character& c, const BakedPalette& baked, const CrowdManager& crowd,
               const Camera& camera, std::vector<uint8_t>* image) {
    CharacterId id;
    ASSERT_TRUE(gl_.addCharacter(c, baked, &id).isOk());
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(gl_.batchLimits()).isOk());
    gl_.clear(kBackground);
    const Status drawn = gl_.drawCrowd(id, crowd.view(), batcher, camera, nullptr);
    ASSERT_TRUE(drawn.isOk()) << drawn.toString();
    ASSERT_TRUE(context_->readPixels(image).isOk());
  }
  void TearDown() override {
    if (gl_started_) gl_.shutdown();
    VulkanRenderFixture::TearDown();
  }

  Renderer gl_;
  bool gl_started_ = false;
};

Status importFan(float fold_tolerance_height, Character* c) {
  GltfImportDesc d;
  d.fold_tolerance_height = fold_tolerance_height;
  return importJson(EightInfluenceFan().file(), c, nullptr, d);
}

TEST_P(VulkanCharacterTest, EightInfluencesDrawWhatOpenGlDraws) {
  SI_START_VULKAN_HOST();
  Character eight, four;
  ASSERT_TRUE(importFan(1e-4f, &eight).isOk());
  ASSERT_TRUE(importFan(std::numeric_limits<float>::infinity(), &four).isOk());
  ASSERT_FALSE(eight.mesh.joints1.empty());
  const Camera camera = Camera::lookAt({0.0, 1.2, 2.4}, {0.0, 1.1, 0.0}, glm::vec3(0, 1, 0), 1.0f,
                                       1.0f, 0.1f, 100.0f);
  std::vector<uint8_t> gl_image, vk_image, gl_four, vk_four;
  ASSERT_NO_FATAL_FAILURE(drawBoth(eight, 3, 0.3, camera, &gl_image, &vk_image));
  ASSERT_NO_FATAL_FAILURE(drawBoth(four, 3, 0.3, camera, &gl_four, &vk_four));
  EXPECT_GT(compare(gl_image, gl_four, nullptr).share, 3 * kMaxDifferingShare)
      << "influences 5 to 8 show in this view";
  const Diff diff = compare(vk_image, gl_image, nullptr);
  EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
  const Diff folded = compare(vk_four, gl_four, nullptr);
  EXPECT_LE(folded.share, kMaxDifferingShare)
      << "folded: max channel difference " << folded.max_channel;
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

TEST_P(VulkanCharacterTest, VertexColoursAndSecondTexcoordsDrawWhatOpenGlDraws) {
  SI_START_VULKAN_HOST();
  PbrAssetDesc painted_desc;
  painted_desc.colors = 3;
  painted_desc.texcoords1 = true;
  Character painted, plain;
  for (const auto& [desc, c] :
       {std::pair{painted_desc, &painted}, std::pair{PbrAssetDesc{}, &plain}}) {
    const std::string json = pbrAsset(desc);
    ASSERT_TRUE(importJson(json, c).isOk());
  }
  ASSERT_FALSE(painted.mesh.colors.empty());
  ASSERT_FALSE(painted.mesh.texcoords1.empty());
  const Camera camera = Camera::lookAt({0.1, 0.6, 1.6}, {0.0, 0.55, 0.0}, glm::vec3(0, 1, 0), 0.9f,
                                       1.0f, 0.1f, 20.0f);
  std::vector<uint8_t> gl_image, vk_image, gl_plain, vk_plain;
  ASSERT_NO_FATAL_FAILURE(drawBoth(painted, 1, 0.5, camera, &gl_image, &vk_image));
  ASSERT_NO_FATAL_FAILURE(drawBoth(plain, 1, 0.5, camera, &gl_plain, &vk_plain));
  EXPECT_GT(compare(gl_image, gl_plain, nullptr).share, 3 * kMaxDifferingShare)
      << "the vertex colours show";
  const Diff diff = compare(vk_image, gl_image, nullptr);
  EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
  const Diff unpainted = compare(vk_plain, gl_plain, nullptr);
  EXPECT_LE(unpainted.share, kMaxDifferingShare)
      << "unpainted: max channel difference " << unpainted.max_channel;
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// Morph targets (tests/render/morph_scenes.h's head of 6 face-like targets, over frames of its
// clip): the morph image, the morph word and each level's cuts reach the vertex stage as si::gl's
// do; the targets show in this view.
TEST_P(VulkanCharacterTest, MorphTargetsDrawWhatOpenGlDraws) {
  SI_START_VULKAN_HOST();
  const Character morphed = morphCharacter(6);
  Character plain = morphed;
  plain.mesh.morph_targets.clear();
  for (Clip& clip : plain.clips) clip.morph_tracks.clear();
  const BakedPalette palette = bakeAt30(morphed), plain_palette = bakeAt30(plain);
  CrowdManager crowd, plain_crowd;
  ASSERT_TRUE(headCrowd(morphed, palette, &crowd).isOk());
  ASSERT_TRUE(headCrowd(plain, plain_palette, &plain_crowd).isOk());
  const Camera camera = headCamera(morphed);
  ASSERT_TRUE(gl_.init(info_, RendererDesc()).isOk());
  gl_started_ = true;
  for (double at : {0.0, 0.4}) {
    SCOPED_TRACE(testing::Message() << "at " << at << " s");
    ASSERT_TRUE(crowd.update(at, camera).isOk());
    ASSERT_TRUE(plain_crowd.update(at, camera).isOk());
    std::vector<uint8_t> gl_image, gl_plain;
    ASSERT_NO_FATAL_FAILURE(glImage(morphed, palette, crowd, camera, &gl_image));
    ASSERT_NO_FATAL_FAILURE(glImage(plain, plain_palette, plain_crowd, camera, &gl_plain));
    EXPECT_GT(compare(gl_image, gl_plain, nullptr).share, 3 * kMaxDifferingShare)
        << "the targets show in this view";
    const std::vector<uint8_t> vk_image = vulkanImage(morphed, palette, crowd, camera);
    const Diff diff = compare(vk_image, gl_image, nullptr);
    EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
  }
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

// Every palette format (half-float matrices, rotation quaternions with translation) draws what
// si::gl draws of it.
TEST_P(VulkanCharacterTest, EveryPaletteFormatDrawsWhatOpenGlDraws) {
  SI_START_VULKAN_HOST();
  ASSERT_TRUE(gl_.init(info_, RendererDesc()).isOk());
  gl_started_ = true;
  for (PaletteFormat format : {PaletteFormat::kMatrix3x4F16, PaletteFormat::kQuatTranslationF32}) {
    SCOPED_TRACE(int(format));
    CrowdDesc cd;
    cd.palette = &palette(format);
    cd.sub_mesh_count = uint32_t(character().mesh.sub_meshes.size());
    cd.lod_count = uint32_t(character().mesh.maxLodCount());
    CrowdManager crowd;
    ASSERT_TRUE(crowd.init(cd).isOk());
    populateLodCrowd(&crowd);
    ASSERT_TRUE(crowd.update(0.2, lodCamera()).isOk());
    std::vector<uint8_t> gl_image;
    ASSERT_NO_FATAL_FAILURE(glImage(character(), palette(format), crowd, lodCamera(), &gl_image));
    const std::vector<uint8_t> vk_image =
        vulkanImage(character(), palette(format), crowd, lodCamera());
    const Diff diff = compare(vk_image, gl_image, nullptr);
    EXPECT_LE(diff.share, kMaxDifferingShare) << "max channel difference " << diff.max_channel;
  }
  EXPECT_TRUE(host_.messages().empty()) << messages();
}

INSTANTIATE_TEST_SUITE_P(Backends, VulkanCharacterTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
