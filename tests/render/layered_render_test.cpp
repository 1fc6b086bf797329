// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Layered animation, the GL half: both skinning paths draw the overlays (the right arm waving
// over the walk, at full weight and half-way through a fade) as the CPU emulation does
// (drawCpuSkinned skins with si::emulateLayeredRecordMatrix), in 64 KiB and 16 KiB batches;
// the overlay shows; depth-only draws put the overlaid arms where the colour draw does; the
// GPU-driven path draws the same image from its own layer records; motion vectors follow the
// overlay; two crowds with other masks draw in one frame, each with its own mask.
#include <functional>

#include "crowd/layer_compose_table.h"
#include "render/layered_scenes.h"
#include "render/render_fixture.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/motion_target.h"

namespace si {
namespace {

using namespace test;

class LayeredRenderTest : public RenderTest {
 protected:
  // The walkers (layered_scenes.h), updated 0.5 s with the close camera.
  void populate(CrowdManager* crowd, const char* branch = "r_clavicle",
                const glm::dvec3& offset = glm::dvec3(0.0)) {
    ASSERT_NO_FATAL_FAILURE(populateWavingCrowd(crowd, &handles_, branch, offset));
    ASSERT_TRUE(crowd->update(0.5, closeView()).isOk());
  }
  // A vertex-shader renderer, the populated crowd and a batcher for it.
  void vertexShaderSetUp(Renderer* r, CrowdManager* crowd, InstanceBatcher* batcher) {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    makeRenderer(r, 0, PaletteFormat::kMatrix3x4F32, &rd);
    makeCrowd(crowd);
    populate(crowd);
    ASSERT_TRUE(batcher->init(r->batchLimits()).isOk());
  }
  static Camera closeView() { return wavingView(); }
  std::vector<InstanceHandle> handles_;
};

TEST_P(LayeredRenderTest, BothSkinningPathsDrawTheEmulatedOverlay) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populate(&crowd);
  ASSERT_EQ(crowd.view().layerRecords().size(), crowd.view().records().size());
  const std::vector<uint8_t> cpu = draw(r, crowd, closeView(), 0, false, nullptr, Path::kCpuSkinned);
  const std::vector<uint8_t> vertex = draw(r, crowd, closeView(), 0);
  const std::vector<uint8_t> compute = draw(r, crowd, closeView(), 0, false, nullptr, Path::kCompute);
  const Diff dv = compare(vertex, cpu, nullptr), dc = compare(compute, cpu, nullptr);
  EXPECT_LE(dv.share, 0.001) << "vertex shader: max channel difference " << dv.max_channel;
  EXPECT_LE(dc.share, 0.001) << "compute: max channel difference " << dc.max_channel;
  // 16 KiB batches: the same layer records through other offsets.
  Renderer r16;
  makeRenderer(&r16, 16384);
  const std::vector<uint8_t> small = draw(r16, crowd, closeView(), 16384);
  EXPECT_EQ(compare(small, vertex, nullptr).max_channel, 0);
  r16.shutdown();
  // The overlay shows: without it (weight 0 at once) the arms are elsewhere.
  for (InstanceHandle h : handles_) ASSERT_TRUE(crowd.stopOverlay(h, 0.0).isOk());
  ASSERT_TRUE(crowd.update(0.0, closeView()).isOk());
  const std::vector<uint8_t> plain = draw(r, crowd, closeView(), 0);
  EXPECT_GT(compare(plain, vertex, nullptr).share, 0.01);
  // With every weight 0 the layered program draws the plain pose: the CPU agrees.
  const std::vector<uint8_t> plain_cpu = draw(r, crowd, closeView(), 0, false, nullptr, Path::kCpuSkinned);
  EXPECT_LE(compare(plain, plain_cpu, nullptr).share, 0.001);
}

// Composed layers (RendererDesc::compose_layers, the default): the vertex-shader path's compose
// pass composes each drawn instance's masked slots once, however many sub-meshes it wears, and
// every slot drawing it reads them; the image is the one the per-vertex chain walk draws
// (composing off), in batches of 64 KiB and of 5 records (each bucket split, so batches hold
// other instances at other offsets), and under storage blocks that hold the instances' rows
// but not a row per drawn slot. The depth-only draw and the compute path's pre-skinning compose
// too.
TEST_P(LayeredRenderTest, ComposedRowsDrawWhatTheChainWalkDraws) {
  Renderer r;
  CrowdManager crowd;
  InstanceBatcher unused;
  vertexShaderSetUp(&r, &crowd, &unused);
  // Storage blocks that hold the rows of 12 instances (the arm's masked slots) and the frame's
  // record ring, but not the rows of their 48 drawn slots.
  const detail::ComposeShape shape =
      detail::composeShape(detail::layerComposeTable(crowd.layerMasks()));
  GlInfo small_blocks = info_;
  small_blocks.max_shader_storage_block_size_bytes = 8192;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.compute_ring_bytes = 8192;
  Renderer small;
  makeRenderer(&small, 0, PaletteFormat::kMatrix3x4F32, &rd, InterpolationChoice::kLinear,
               &small_blocks);
  for (uint32_t per_draw : {0u, 5u}) {
    SCOPED_TRACE(per_draw);
    BatchLimits limits = r.batchLimits();
    limits.max_instances_per_draw = per_draw;
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(limits).isOk());
    const auto drawn = [&](Renderer& renderer, bool compose, DrawStats* stats,
                           DrawMode mode = DrawMode::kDefault) {
      renderer.setComposeLayers(compose);
      renderer.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      EXPECT_TRUE(renderer.drawCrowd(CharacterId{}, crowd.view(), batcher, closeView(), stats, mode)
                      .isOk());
      std::vector<uint8_t> rgba;
      EXPECT_TRUE(context_->readPixels(&rgba).isOk());
      return rgba;
    };
    DrawStats composed_stats, walk_stats, small_stats;
    const std::vector<uint8_t> composed = drawn(r, true, &composed_stats);
    const std::vector<uint8_t> walk = drawn(r, false, &walk_stats);
    const std::vector<uint8_t> in_small = drawn(small, true, &small_stats);
    EXPECT_EQ(small_stats.compose_dispatches, 1u);
    EXPECT_LE(detail::composedRowBytes(composed_stats.composed_records, shape),
              small_blocks.max_shader_storage_block_size_bytes);
    EXPECT_GT(detail::composedRowBytes(composed_stats.instances, shape),
              small_blocks.max_shader_storage_block_size_bytes);
    EXPECT_EQ(compare(in_small, composed, nullptr).max_channel, 0);
    EXPECT_EQ(composed_stats.compose_dispatches, 1u);
    // 12 instances, each composed once, drawn in 4 sub-meshes' batches.
    EXPECT_EQ(composed_stats.composed_records, crowd.view().records().size());
    EXPECT_EQ(composed_stats.instances, 4 * crowd.view().records().size());
    EXPECT_EQ(walk_stats.compose_dispatches, 0u);
    const Diff d = compare(composed, walk, nullptr);
    EXPECT_LE(d.share, 0.0005) << "max channel difference " << d.max_channel;
    EXPECT_LE(d.max_channel, 8);
    // Pre-skinning reads the rows too: the compute path's image is its walk's.
    DrawStats compute_stats, compute_walk_stats;
    const std::vector<uint8_t> compute = drawn(r, true, &compute_stats, DrawMode::kComputeSkinned);
    const std::vector<uint8_t> compute_walk =
        drawn(r, false, &compute_walk_stats, DrawMode::kComputeSkinned);
    EXPECT_EQ(compute_stats.compose_dispatches, 1u);
    EXPECT_EQ(compute_walk_stats.compose_dispatches, 0u);
    const Diff dc = compare(compute, compute_walk, nullptr);
    EXPECT_LE(dc.share, 0.0005) << "compute: max channel difference " << dc.max_channel;
  }
  small.shutdown();
  r.setComposeLayers(true);
  DrawStats depth_stats;
  ASSERT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), unused, closeView(), &depth_stats,
                          DrawMode::kDepthOnly)
                  .isOk());
  EXPECT_EQ(depth_stats.compose_dispatches, 1u);
  r.shutdown();
}

// Two crowds with other masks (the right arm, the left arm) drawn one after the other into one
// frame, nothing read back between them: each draw reads its own crowd's mask table, on both
// skinning paths, as the CPU emulation draws the two.
TEST_P(LayeredRenderTest, TwoCrowdsWithOtherMasksDrawInOneFrame) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager right, left;
  makeCrowd(&right);
  makeCrowd(&left);
  populate(&right);
  populate(&left, "l_clavicle", glm::dvec3(0.6, 0.0, -0.75));
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  const auto drawBoth = [&](const std::function<Status(const CrowdManager&)>& drawOne) {
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    EXPECT_TRUE(drawOne(right).isOk());
    EXPECT_TRUE(drawOne(left).isOk());
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  };
  const std::vector<uint8_t> cpu = drawBoth([&](const CrowdManager& c) {
    return r.drawCpuSkinned(CharacterId{}, c.view(), closeView(), nullptr);
  });
  const std::vector<uint8_t> vertex = drawBoth([&](const CrowdManager& c) {
    return r.drawCrowd(CharacterId{}, c.view(), batcher, closeView(), nullptr);
  });
  const std::vector<uint8_t> compute = drawBoth([&](const CrowdManager& c) {
    return r.drawCrowd(CharacterId{}, c.view(), batcher, closeView(), nullptr,
                       DrawMode::kComputeSkinned);
  });
  const Diff dv = compare(vertex, cpu, nullptr), dc = compare(compute, cpu, nullptr);
  EXPECT_LE(dv.share, 0.001) << "vertex shader: max channel difference " << dv.max_channel;
  EXPECT_LE(dc.share, 0.001) << "compute: max channel difference " << dc.max_channel;
  if (HasFailure()) {  // Which path drew what: the three frames beside the test's temp files.
    const std::string base = ::testing::TempDir() + "si_two_crowds_" + headlessBackendName(GetParam());
    (void)writePng(base + "_cpu.png", kSize, kSize, cpu);
    (void)writePng(base + "_vertex.png", kSize, kSize, vertex);
    (void)writePng(base + "_compute.png", kSize, kSize, compute);
  }
  // The left crowd's mask shows: drawn with the right arm's mask it looks otherwise.
  CrowdManager both_right;
  makeCrowd(&both_right);
  handles_.clear();
  populate(&both_right, "r_clavicle", glm::dvec3(0.6, 0.0, -0.75));
  r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
  ASSERT_TRUE(r.drawCrowd(CharacterId{}, right.view(), batcher, closeView(), nullptr).isOk());
  ASSERT_TRUE(r.drawCrowd(CharacterId{}, both_right.view(), batcher, closeView(), nullptr).isOk());
  std::vector<uint8_t> wrong_mask;
  ASSERT_TRUE(context_->readPixels(&wrong_mask).isOk());
  EXPECT_GT(compare(wrong_mask, vertex, nullptr).share, 0.005);
  r.shutdown();
}

// A depth pre-pass of a crowd playing overlays writes the depth the colour draw writes (the
// layered depth-only programs, drawCrowd's and the GPU-driven path's), not the pose without
// the overlay.
TEST_P(LayeredRenderTest, DepthOnlyDrawsTheOverlaidPose) {
  Renderer r;
  CrowdManager crowd;
  InstanceBatcher batcher;
  vertexShaderSetUp(&r, &crowd, &batcher);
  MotionTarget target;
  ASSERT_TRUE(target.create(kSize, kSize).isOk());
  const auto depthOf = [&](DrawMode mode) {
    target.clear(glm::vec4(0.0f));
    EXPECT_TRUE(
        r.drawCrowd(CharacterId{}, crowd.view(), batcher, closeView(), nullptr, mode).isOk());
    std::vector<float> depth;
    EXPECT_TRUE(target.readDepth(&depth).isOk());
    return depth;
  };
  const std::vector<float> colour = depthOf(DrawMode::kSkinned);
  const std::vector<float> depth_only = depthOf(DrawMode::kDepthOnly);
  ASSERT_EQ(colour.size(), size_t(kSize) * kSize);
  EXPECT_EQ(differingDepths(colour, depth_only), 0u);
  // The GPU-driven depth-only draw (vertex-shader skinning: composed rows) writes it too.
  target.clear(glm::vec4(0.0f));
  DrawStats gpu_stats;
  ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeView(), &gpu_stats,
                                   DrawMode::kDepthOnly)
                  .isOk());
  EXPECT_EQ(gpu_stats.compose_dispatches, 1u);
  std::vector<float> gpu_depth;
  ASSERT_TRUE(target.readDepth(&gpu_depth).isOk());
  EXPECT_LE(differingDepths(colour, gpu_depth), colour.size() / 1000);
  for (InstanceHandle h : handles_) ASSERT_TRUE(crowd.stopOverlay(h, 0.0).isOk());
  ASSERT_TRUE(crowd.update(0.0, closeView()).isOk());
  const std::vector<float> plain = depthOf(DrawMode::kDepthOnly);
  EXPECT_GT(differingDepths(plain, depth_only), colour.size() / 100);  // The arms moved.
  target.restore();
  target.release();
  r.shutdown();
}

// The GPU-driven path writes each visible instance's layer record in its cull pass, at the
// crowd's clock, and both its draws (vertex-shader skinning, from composed rows, and
// pre-skinning) skin with it: the image drawCrowd draws from update()'s layer records.
TEST_P(LayeredRenderTest, TheGpuDrivenPathDrawsTheOverlays) {
  RendererDesc rd;
  rd.measure_gpu_time = true;  // The selection's counts are read back after the timer.
  Renderer r;
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populate(&crowd);
  const std::vector<uint8_t> reference = draw(r, crowd, closeView(), 0);
  for (DrawMode mode : {DrawMode::kSkinned, DrawMode::kComputeSkinned}) {
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    DrawStats stats;
    const Status s = r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeView(), &stats, mode);
    ASSERT_TRUE(s.isOk()) << s.toString();
    EXPECT_EQ(stats.gpu_visible, crowd.view().stats().visible);
    // Both skinnings read composed rows: one compose pass.
    EXPECT_EQ(stats.compose_dispatches, 1u);
    std::vector<uint8_t> gpu;
    ASSERT_TRUE(context_->readPixels(&gpu).isOk());
    const Diff d = compare(gpu, reference, nullptr);
    EXPECT_LE(d.share, 0.001) << (mode == DrawMode::kSkinned ? "vertex shader" : "pre-skinned")
                              << ": max channel difference " << d.max_channel;
  }
  // Without the layer records (every overlay stopped at once) the GPU draws the plain pose,
  // which the overlaid image is not.
  for (InstanceHandle h : handles_) ASSERT_TRUE(crowd.stopOverlay(h, 0.0).isOk());
  r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
  ASSERT_TRUE(
      r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeView(), nullptr, DrawMode::kSkinned)
          .isOk());
  std::vector<uint8_t> plain;
  ASSERT_TRUE(context_->readPixels(&plain).isOk());
  EXPECT_GT(compare(plain, reference, nullptr).share, 0.01);
  r.shutdown();
}

// Motion vectors of overlays: the previous position is skinned with the previous layer record.
// With the camera and the base clips still, only the overlay moves: its arms have motion while
// it plays, and none at all when it is held still too (so neither the current layer record nor
// none stands in for the previous one). Both skinning paths and both GPU-driven draws (their
// own previous layer records) agree.
TEST_P(LayeredRenderTest, MotionVectorsFollowTheOverlay) {
  RendererDesc rd;
  rd.motion_vectors = true;
  rd.gpu_driven_ring_bytes = 4u << 20;
  rd.skinning_path = SkinningPath::kVertexShader;  // Every draw names its mode: no timing.
  Renderer r;
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  MotionTarget target;
  ASSERT_TRUE(target.create(kSize, kSize).isOk());
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(character().skeleton, palette(), "right arm", {"r_clavicle"}, &arm).isOk());
  const uint32_t walk = uint32_t(palette().findClip("walk")), wave = uint32_t(palette().findClip("wave"));
  // Two frames 0.05 s apart: drawCrowd draws the second; the GPU-driven path draws both.
  const auto motionOf = [&](float overlay_speed, DrawMode mode, bool gpu_driven,
                            std::vector<glm::vec2>* motion, float base_speed = 0.0f) {
    CrowdManager crowd;
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = 4;
    cd.lod_count = 1;
    cd.previous_records = true;
    ASSERT_TRUE(crowd.init(cd).isOk());
    uint32_t mask = 0;
    ASSERT_TRUE(crowd.addLayerMask(arm, &mask).isOk());
    for (int k = 0; k < 8; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k % 4 - 1.5) * 1.2, 0.0, -2.5 - 1.5 * (k / 4));
      d.clip = walk;
      d.time_seconds = 0.11 * k;
      d.speed = base_speed;  // The base pose holds still (by default).
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(d, &h).isOk());
      ASSERT_TRUE(crowd.playOverlay(h, wave, mask, 1.0f, 0.0, 0.9 + 0.1 * k, overlay_speed).isOk());
    }
    ASSERT_TRUE(crowd.update(0.0, closeView()).isOk());
    if (gpu_driven) {
      ASSERT_TRUE(
          r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeView(), nullptr, mode).isOk());
      ASSERT_TRUE(crowd.advance(0.05).isOk());
      target.clear(glm::vec4(0.0f));
      const Status s =
          r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeView(), nullptr, mode);
      ASSERT_TRUE(s.isOk()) << s.toString();
      ASSERT_TRUE(target.readMotion(motion).isOk());
      return;
    }
    ASSERT_TRUE(crowd.update(0.05, closeView()).isOk());
    ASSERT_EQ(crowd.view().previousLayerRecords().size(), crowd.view().previousRecords().size());
    target.clear(glm::vec4(0.0f));
    const Status s = r.drawCrowd(CharacterId{}, crowd.view(), batcher, closeView(), nullptr, mode);
    ASSERT_TRUE(s.isOk()) << s.toString();
    ASSERT_TRUE(target.readMotion(motion).isOk());
  };
  std::vector<glm::vec2> waving_vs, waving_cs, still, gpu_vs, gpu_cs, gpu_still;
  motionOf(1.0f, DrawMode::kSkinned, false, &waving_vs);
  motionOf(1.0f, DrawMode::kComputeSkinned, false, &waving_cs);
  motionOf(0.0f, DrawMode::kSkinned, false, &still);
  motionOf(1.0f, DrawMode::kSkinned, true, &gpu_vs);
  motionOf(1.0f, DrawMode::kComputeSkinned, true, &gpu_cs);
  motionOf(0.0f, DrawMode::kComputeSkinned, true, &gpu_still);
  std::printf("[ layered  ] largest motion: waving %.2f px, held %.4f px\n",
              largestMotionPixels(waving_vs), largestMotionPixels(still));
  EXPECT_GT(largestMotionPixels(waving_vs), 0.5f);
  EXPECT_LT(largestMotionPixels(still), 1e-3f);
  EXPECT_LT(largestMotionPixels(gpu_still), 1e-3f);
  // Both skinning paths and both GPU-driven draws agree.
  for (const std::vector<glm::vec2>* other : {&waving_cs, &gpu_vs, &gpu_cs}) {
    SCOPED_TRACE(other - &waving_vs);
    expectMotionAgrees(waving_vs, *other);
  }
  // Walking and waving: the composed previous rows (previous records and previous layer
  // records) move as the per-vertex chain walk's, and as pre-skinning's.
  std::vector<glm::vec2> walking_composed, walking_walk, walking_cs;
  motionOf(1.0f, DrawMode::kSkinned, false, &walking_composed, 1.0f);
  motionOf(1.0f, DrawMode::kComputeSkinned, false, &walking_cs, 1.0f);
  r.setComposeLayers(false);
  motionOf(1.0f, DrawMode::kSkinned, false, &walking_walk, 1.0f);
  r.setComposeLayers(true);
  expectMotionAgrees(walking_composed, walking_walk);
  expectMotionAgrees(walking_composed, walking_cs);
  target.restore();
  target.release();
  r.shutdown();
}

// Rigid instancing draws the instances unskinned: overlays change nothing there.
TEST_P(LayeredRenderTest, RigidDrawsIgnoreTheOverlays) {
  Renderer r;
  CrowdManager crowd;
  InstanceBatcher batcher;
  vertexShaderSetUp(&r, &crowd, &batcher);
  EXPECT_TRUE(
      r.drawCrowd(CharacterId{}, crowd.view(), batcher, closeView(), nullptr, DrawMode::kRigid)
          .isOk());
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, LayeredRenderTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
