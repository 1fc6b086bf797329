// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A character that keeps 8 influences a vertex (tests/gltf/eight_influence_asset.h, imported
// past its fold tolerance) draws on every path what the CPU emulation draws with all 8, over
// frames of its clip, and visibly not what the same character folded to 4 draws (issue "Any
// animated glTF becomes a crowd", part 3).
#include <limits>

#include "gltf/eight_influence_asset.h"
#include "gltf/import_json.h"
#include "render/render_fixture.h"
#include "render/skinning_paths.h"
#include "si/core/reference_evaluator.h"
#include "si/crowd/crowd_manager.h"
#include "si/gltf/gltf_import.h"

namespace si {
namespace {

using namespace test;

class EightInfluenceRenderTest : public RenderTest {};

Status importFan(float fold_tolerance_height, Character* c) {
  GltfImportDesc d;
  d.fold_tolerance_height = fold_tolerance_height;
  return importJson(EightInfluenceFan().file(), c, nullptr, d);
}

// The fan's three instances, at different times of its clip and tinted apart, in a crowd of
// `palette`.
Status fanCrowd(const BakedPalette& palette, CrowdManager* crowd) {
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = 1;
  cd.lod_count = 1;
  Status s = crowd->init(cd);
  for (int k = 0; k < 3 && s.isOk(); ++k) {
    InstanceDesc d;
    d.position = glm::dvec3(-1.6 + 1.6 * k, 0.0, 0.0);
    d.time_seconds = 0.3 + 0.3 * k;
    d.color = glm::u8vec4(uint8_t(120 + 60 * k), 200, 160, 255);
    InstanceHandle h;
    s = crowd->add(d, &h);
  }
  return s;
}

// Close enough to the fans that where influences 5 to 8 put their vertices shows.
Camera fanCamera() {
  return Camera::lookAt({0.0, 1.2, 2.4}, {0.0, 1.1, 0.0}, glm::vec3(0, 1, 0), 1.0f, 1.0f, 0.1f,
                        100.0f);
}

TEST_P(EightInfluenceRenderTest, EveryPathDrawsAllEight) {
  Character eight, four;
  ASSERT_TRUE(importFan(1e-4f, &eight).isOk());
  ASSERT_TRUE(importFan(std::numeric_limits<float>::infinity(), &four).isOk());
  ASSERT_FALSE(eight.mesh.joints1.empty());
  ASSERT_TRUE(four.mesh.joints1.empty());
  BakedPalette palette, folded_palette;
  ASSERT_TRUE(bakePalette(eight, BakeDesc(), &palette, nullptr).isOk());
  ASSERT_TRUE(bakePalette(four, BakeDesc(), &folded_palette, nullptr).isOk());
  Renderer r;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  ASSERT_TRUE(r.init(info_, rd).isOk());
  CharacterId id, folded;
  ASSERT_TRUE(r.addCharacter(eight, palette, &id).isOk());
  ASSERT_TRUE(r.addCharacter(four, folded_palette, &folded).isOk());
  // The same three instances in a crowd of each palette.
  CrowdManager crowd, folded_crowd;
  ASSERT_TRUE(fanCrowd(palette, &crowd).isOk());
  ASSERT_TRUE(fanCrowd(folded_palette, &folded_crowd).isOk());
  const Camera camera = fanCamera();
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  const glm::vec4 background(0.2f, 0.25f, 0.3f, 1.0f);
  for (int frame = 0; frame < 3; ++frame) {
    ASSERT_TRUE(crowd.update(frame == 0 ? 0.0 : 0.15, camera).isOk());
    ASSERT_TRUE(folded_crowd.update(frame == 0 ? 0.0 : 0.15, camera).isOk());
    const std::vector<uint8_t> folded_image =
        cpuSkinnedImage(r, folded, folded_crowd.view(), camera, background, *context_);
    const std::vector<uint8_t> emulated =
        cpuSkinnedImage(r, id, crowd.view(), camera, background, *context_);
    EXPECT_GT(compare(emulated, folded_image, nullptr).share, 3 * kMaxDifferingShare)
        << "influences 5 to 8 show in this view";
    SCOPED_TRACE(testing::Message() << "frame " << frame);
    expectEveryPathDraws(r, id, crowd.view(), batcher, camera, background, *context_, emulated);
  }
  r.shutdown();
}

// The captures (the vertex shader's through transform feedback, the compute pre-skinning
// pass's buffer) skin all 8 too: the fan's 8-influence vertices where the reference with all 8
// puts them, within the bake's error, and far from where their 4 largest would.
TEST_P(EightInfluenceRenderTest, TheCapturesSkinAllEight) {
  Character eight;
  ASSERT_TRUE(importFan(1e-4f, &eight).isOk());
  BakedPalette palette;
  BakeReport report;
  ASSERT_TRUE(bakePalette(eight, BakeDesc(), &palette, &report).isOk());
  Renderer r;
  ASSERT_TRUE(r.init(info_, RendererDesc()).isOk());
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(eight, palette, &id).isOk());
  const EightInfluenceFan fan;
  for (double t : {0.5, 0.9}) {
    const InstanceRecord rec = clipRecord(palette, 0, t);
    ReferencePose pose;
    ASSERT_TRUE(evaluateLocalPose(eight.skeleton, eight.clips[0], t, &pose).isOk());
    std::vector<glm::dvec3> reference(eight.mesh.vertexCount());
    ASSERT_TRUE(skinVertices(eight.mesh, pose.skinning, reference, {}, {}).isOk());
    for (SkinningPath path : {SkinningPath::kVertexShader, SkinningPath::kCompute}) {
      SCOPED_TRACE(testing::Message()
                   << (path == SkinningPath::kCompute ? "compute" : "vertex") << " t=" << t);
      std::vector<glm::vec3> gpu;
      ASSERT_TRUE(r.captureSkinnedPositions(id, rec, &gpu, path).isOk());
      ASSERT_EQ(gpu.size(), reference.size());
      for (int v = 0; v < 3; ++v) {  // The vertices with 8 influences.
        const double error = glm::length(glm::dvec3(gpu[size_t(v)]) - reference[size_t(v)]);
        EXPECT_LE(error, report.max_error_units + 2e-5) << v;
        EXPECT_GT(glm::length(fan.skinned(v, t, true) - reference[size_t(v)]), 10.0 * error + 1e-3)
            << v << ": the 4 largest would put it elsewhere";
      }
    }
  }
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, EightInfluenceRenderTest, allBackends(), backendTestName);

// The OpenGL ES profile (GLSL ES 3.00, the vertex-shader path only) draws the fan with all 8
// as a desktop context's CPU emulation does.
class EightInfluenceEsTest : public RenderTest {
 protected:
  bool es() const override { return true; }
  // The fan's crowd (fanCrowd) drawn on the current context, by the CPU emulation with `cpu`,
  // else by the vertex-shader path.
  std::vector<uint8_t> drawFan(bool cpu) {
    Character eight;
    EXPECT_TRUE(importFan(1e-4f, &eight).isOk());
    BakedPalette palette;
    EXPECT_TRUE(bakePalette(eight, BakeDesc(), &palette, nullptr).isOk());
    CrowdManager crowd;
    EXPECT_TRUE(fanCrowd(palette, &crowd).isOk());
    return drawCrowdImage(eight, palette, crowd, fanCamera(), cpu);
  }
};

TEST_P(EightInfluenceEsTest, TheEsProfileDrawsAllEight) {
  expectEsDrawsAsDesktopCpu([this](bool cpu) { return drawFan(cpu); });
}

INSTANTIATE_TEST_SUITE_P(Backends, EightInfluenceEsTest, esBackends(), backendTestName);

}  // namespace
}  // namespace si
