// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// 2D blend spaces, the GL half: a crowd blending four clips each (a 2 x 2 grid of the default
// palette's idle, walk, run and wave), at points inside cells and on grid lines, some fading in
// from their clip, beside plain overlays, is drawn by every path as the CPU emulation
// (emulateLayeredChain through the extra layer records) draws it; the extra layers show;
// motion vectors follow a moving blend point; depth-only draws write the colour draw's depth.
#include <cstring>
#include <utility>

#include "render/layered_scenes.h"
#include "render/render_fixture.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/motion_target.h"

namespace si {
namespace {

using namespace test;

class Blend2dRenderTest : public RenderTest {
 protected:
  // A crowd with the body mask (0), the arm mask (1) and the 2D space (0) over the grid.
  void setUpCrowd(CrowdManager* crowd, bool previous_records = false, uint32_t lods = 3) {
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = 4;
    cd.lod_count = lods;
    cd.previous_records = previous_records;
    ASSERT_TRUE(crowd->init(cd).isOk());
    LayerMask body, arm;
    ASSERT_TRUE(buildFullBodyMask(character().skeleton, palette(), "body", &body).isOk());
    ASSERT_TRUE(
        buildLayerMask(character().skeleton, palette(), "arm", {"r_clavicle"}, &arm).isOk());
    uint32_t id = 0;
    ASSERT_TRUE(crowd->addLayerMask(body, &id).isOk());
    ASSERT_TRUE(crowd->addLayerMask(arm, &id).isOk());
    ASSERT_TRUE(crowd->addBlendSpace(idleWalkRunWaveGrid(0), &id).isOk());
  }
  // 12 instances: two thirds blend at points over the grid (inside cells, on its lines, one at a
  // corner), a third of those fading in; every fourth waves its arm instead (an overlay).
  void populate(CrowdManager* crowd, bool previous_records = false) {
    setUpCrowd(crowd, previous_records);
    const glm::vec2 points[] = {{0.3f, 0.6f}, {0.8f, 0.2f},  {0.5f, 0.0f}, {0.0f, 0.7f},
                                {1.0f, 1.0f}, {0.45f, 0.9f}, {0.7f, 0.5f}, {0.15f, 0.35f}};
    const uint32_t walk = uint32_t(palette().findClip("walk"));
    const uint32_t wave = uint32_t(palette().findClip("wave"));
    size_t blended = 0;
    for (int k = 0; k < 12; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k % 4 - 1.5) * 1.2, 0.0, -2.5 - 1.5 * (k / 4));
      d.rotation = glm::angleAxis(0.6f * float(k % 3 - 1) - 0.5f, glm::vec3(0, 1, 0));
      d.clip = walk;
      d.time_seconds = 0.13 * k;
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
      handles_.push_back(h);
      if (k % 4 == 3) {
        ASSERT_TRUE(crowd->playOverlay(h, wave, 1, 1.0f, 0.0, 0.1 * k).isOk());
      } else if (k % 3 != 2 || blended < 8) {
        const glm::vec2 p = points[blended++ % 8];
        ASSERT_TRUE(crowd->playBlend(h, 0, p, k % 3 == 0 ? 1.0 : 0.0, 0.07 * k).isOk());
      }
    }
    ASSERT_TRUE(crowd->update(0.4, view()).isOk());
  }
  static Camera view() {
    return Camera::lookAt({0.0, 1.6, 2.5}, {0.0, 1.0, -4.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                          100.0f);
  }
  std::vector<InstanceHandle> handles_;
};

TEST_P(Blend2dRenderTest, EveryPathDrawsTheEmulatedBlend) {
  Renderer r, pre;
  RendererDesc vs;
  vs.skinning_path = SkinningPath::kVertexShader;
  vs.measure_gpu_time = true;  // The GPU-driven path's counts are read back with its timing.
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &vs);
  RendererDesc compute = vs;
  compute.skinning_path = SkinningPath::kCompute;
  makeRenderer(&pre, 0, PaletteFormat::kMatrix3x4F32, &compute);
  CrowdManager crowd;
  populate(&crowd);
  ASSERT_EQ(crowd.view().extraLayerRecords().size(),
            crowd.view().records().size() * kExtraLayerRecords);
  size_t with_extras = 0;
  for (const LayerRecord& l : crowd.view().layerRecords()) with_extras += layerHasExtras(l);
  ASSERT_GT(with_extras, 4u);
  DrawStats cpu_stats;
  const std::vector<uint8_t> cpu = draw(r, crowd, view(), 0, false, &cpu_stats, Path::kCpuSkinned);
  expectEveryCaseDraws(
      {{"vertex shader", &r, Path::kInstanced, false, DrawMode::kSkinned},
       {"compute", &pre, Path::kCompute, false, DrawMode::kComputeSkinned},
       {"gpu-driven", &r, Path::kInstanced, true, DrawMode::kSkinned},
       {"gpu-driven pre-skinned", &r, Path::kInstanced, true, DrawMode::kComputeSkinned}},
      crowd, view(), cpu, cpu_stats);
  // The extra layers show: every blend moved to the cell's bottom edge (y 0: its first two
  // clips alone) draws another image.
  for (InstanceHandle h : handles_) {
    uint32_t space = 0;
    glm::vec2 p;
    double phase = 0.0;
    if (crowd.blendState(h, &space, &p, &phase).isOk()) {
      ASSERT_TRUE(crowd.setBlendParameter(h, glm::vec2(p.x, 0.0f)).isOk());
    }
  }
  ASSERT_TRUE(crowd.update(0.0, view()).isOk());
  EXPECT_GT(compare(draw(r, crowd, view(), 0), cpu, nullptr).share, 0.003);
  r.shutdown();
  pre.shutdown();
}

// Drawn without composed layers (the per-vertex chain walk), 2D blends are refused by name.
TEST_P(Blend2dRenderTest, UncomposedDrawsRefuseTheExtraLayers) {
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.compose_layers = false;
  Renderer r;
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
  CrowdManager crowd;
  populate(&crowd);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  for (const Status& s : {r.drawCrowd(CharacterId{}, crowd.view(), batcher, view(), nullptr),
                          r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), view(), nullptr)}) {
    EXPECT_EQ(s.code(), StatusCode::kUnsupported) << s.toString();
    EXPECT_NE(s.message().find("2D blends"), std::string::npos) << s.message();
  }
  r.shutdown();
}

// Motion vectors of a blend whose point moves across the grid between two updates agree on
// drawCrowd's paths and the GPU-driven ones, and depth-only draws write the colour draw's depth.
TEST_P(Blend2dRenderTest, MotionAndDepthFollowTheBlend) {
  RendererDesc rd;
  rd.motion_vectors = true;
  rd.skinning_path = SkinningPath::kVertexShader;
  Renderer r;
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  MotionTarget target;
  ASSERT_TRUE(target.create(kSize, kSize).isOk());
  const Camera camera = view();
  const auto motionOf = [&](DrawMode mode, glm::vec2 to, std::vector<glm::vec2>* motion,
                            bool gpu_driven = false) {
    CrowdManager crowd;
    setUpCrowd(&crowd, true, 1);
    InstanceDesc d;
    d.position = glm::dvec3(0.0, 0.0, -2.8);
    d.rotation = glm::angleAxis(-0.9f, glm::vec3(0, 1, 0));
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    ASSERT_TRUE(crowd.playBlend(h, 0, glm::vec2(0.2f, 0.3f), 0.0, 0.3).isOk());
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    if (gpu_driven) {
      ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, nullptr, mode).isOk());
    }
    ASSERT_TRUE(crowd.setBlendParameter(h, to).isOk());
    if (gpu_driven) {
      ASSERT_TRUE(crowd.advance(0.05).isOk());
    } else {
      ASSERT_TRUE(crowd.update(0.05, camera).isOk());
    }
    target.clear(glm::vec4(0.0f));
    const Status s = gpu_driven
                         ? r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, nullptr, mode)
                         : r.drawCrowd(CharacterId{}, crowd.view(), batcher, camera, nullptr, mode);
    ASSERT_TRUE(s.isOk()) << s.toString();
    ASSERT_TRUE(target.readMotion(motion).isOk());
  };
  std::vector<glm::vec2> vs, cs, gpu_vs, gpu_cs, still;
  motionOf(DrawMode::kSkinned, glm::vec2(0.7f, 0.9f), &vs);
  motionOf(DrawMode::kComputeSkinned, glm::vec2(0.7f, 0.9f), &cs);
  motionOf(DrawMode::kSkinned, glm::vec2(0.7f, 0.9f), &gpu_vs, true);
  motionOf(DrawMode::kComputeSkinned, glm::vec2(0.7f, 0.9f), &gpu_cs, true);
  const std::pair<const char*, const std::vector<glm::vec2>*> others[] = {
      {"compute", &cs}, {"gpu-driven", &gpu_vs}, {"gpu-driven pre-skinned", &gpu_cs}};
  for (const auto& [name, other] : others) {
    SCOPED_TRACE(name);
    expectMotionAgrees(vs, *other);
  }
  // Towards another point the motion differs (the extra layers move it).
  motionOf(DrawMode::kSkinned, glm::vec2(0.7f, 0.3f), &still);
  size_t differ = 0;
  for (size_t i = 0; i < vs.size(); ++i) differ += glm::length(vs[i] - still[i]) > 1e-3f;
  EXPECT_GT(differ, 20u);
  // Depth-only: the colour draw's depth.
  CrowdManager crowd;
  populate(&crowd, true);
  const auto depthOf = [&](DrawMode mode, bool gpu_driven = false) {
    target.clear(glm::vec4(0.0f));
    const Status s = gpu_driven
                         ? r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), view(), nullptr, mode)
                         : r.drawCrowd(CharacterId{}, crowd.view(), batcher, view(), nullptr, mode);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<float> depth;
    EXPECT_TRUE(target.readDepth(&depth).isOk());
    return depth;
  };
  const std::vector<float> colour = depthOf(DrawMode::kSkinned);
  ASSERT_EQ(colour.size(), size_t(kSize) * kSize);
  EXPECT_EQ(differingDepths(colour, depthOf(DrawMode::kDepthOnly)), 0u);
  EXPECT_LE(differingDepths(colour, depthOf(DrawMode::kDepthOnly, true)), colour.size() / 1000);
  target.restore();
  target.release();
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, Blend2dRenderTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
