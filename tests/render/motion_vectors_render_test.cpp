// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Motion vectors, the GL half. An engine's own program built on the public include
// (si_skinning.glsl with SI_PREVIOUS_RECORDS, InstanceBatcher::buildPrevious) draws each vertex
// at its previous position with the previous camera: that image is the previous frame's image,
// pixel for pixel, across crossfades and speed changes. The renderer's motion output on both
// skinning paths equals what that program computes from the same records (the GPU-driven path:
// gpu_driven_motion_render_test.cpp, whose tests this file's instantiation runs too).
#include "render/motion_vector_fixture.h"

namespace si {
namespace test {
// Drawing frame N+1 at each vertex's previous position with frame N's camera gives frame N's
// image exactly; drawing it where it is now does not.
TEST_P(MotionVectorTest, PreviousPositionsDrawTheLastFrame) {
  ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());  // Frame N.
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<uint8_t> frame_n = colors();
  nextFrame();
  ASSERT_EQ(crowd_.view().records().size(), handles_.size());  // Every instance in view in both.
  target_.clear(glm::vec4(0.0f));
  drawEngine(true);
  const std::vector<uint8_t> previous = colors();
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<uint8_t> frame_n1 = colors();
  size_t covered = 0;
  for (size_t p = 3; p < frame_n.size(); p += 4) covered += frame_n[p] != 0;
  EXPECT_GT(covered, size_t(kSize) * kSize / 10);
  EXPECT_EQ(differingPixels(previous, frame_n), 0u);
  EXPECT_GT(differingPixels(frame_n1, frame_n), covered / 4);  // There was motion.
}

// The renderer's motion output, on both skinning paths, equals the engine program's (the same
// records, the same cameras) where both drew; nothing is written for paths that draw none. Two
// instances placed anew between the frames have no previous record: the renderer (which reads
// previous records through indices) takes buildPrevious's fallback, the camera's motion only.
TEST_P(MotionVectorTest, TheRendererWritesTheIncludesMotion) {
  ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
  for (size_t k : {5u, 10u}) {
    InstanceDesc d;
    ASSERT_TRUE(crowd_.get(handles_[k], &d).isOk());
    ASSERT_TRUE(crowd_.setTransform(handles_[k], d.position, d.rotation, d.scale).isOk());
  }
  nextFrame();
  EXPECT_EQ(std::count(crowd_.view().previousRecordIndices().begin(),
                       crowd_.view().previousRecordIndices().end(), kNoPreviousRecord),
            2);
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<glm::vec2> expected = motions();
  const std::vector<float> expected_depth = depths();
  float largest = 0.0f;
  for (const glm::vec2& m : expected) largest = std::max(largest, glm::length(m));
  EXPECT_GT(largest, 0.02f);  // At least 5 pixels somewhere.
  for (SkinningPath path : {SkinningPath::kVertexShader, SkinningPath::kCompute}) {
    SCOPED_TRACE(skinningPathName(path));
    Renderer r;
    makeMotionRenderer(&r, path);
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
    target_.clear(glm::vec4(0.0f));
    const Status s =
        r.drawCrowd(CharacterId{}, crowd_.view(), batcher, crowd_.view().camera(), nullptr);
    ASSERT_TRUE(s.isOk()) << s.toString();
    const std::vector<glm::vec2> motion = motions();
    const std::vector<float> depth = depths();
    size_t compared = 0, within = 0;
    double worst = 0.0;
    for (size_t p = 0; p < motion.size(); ++p) {
      if (depth[p] >= 1.0f || expected_depth[p] >= 1.0f) continue;  // Drawn by both.
      ++compared;
      const double off = glm::length(motion[p] - expected[p]);
      within += off <= 1e-4;  // 0.026 pixels.
      worst = std::max(worst, off);
    }
    EXPECT_GT(compared, size_t(kSize) * kSize / 10);
    // Silhouette pixels may come from another triangle where rounding differs.
    EXPECT_GE(double(within), 0.995 * double(compared)) << "worst " << worst;
    // The target's summary: the drawn pixels and their motion in pixels.
    MotionSummary summary;
    ASSERT_TRUE(target_.summarize(&summary).isOk());
    EXPECT_EQ(summary.drawn_pixels, size_t(std::count_if(depth.begin(), depth.end(),
                                                         [](float z) { return z < 1.0f; })));
    EXPECT_NEAR(summary.max_pixels, double(largest) * kSize, 0.5);
    EXPECT_GT(summary.mean_pixels, 0.5);
    // Motion vectors only from drawCrowd and drawCrowdGpuCulled.
    EXPECT_EQ(
        r.drawTraditional(CharacterId{}, crowd_.view(), crowd_.view().camera(), nullptr).code(),
        StatusCode::kUnsupported);
    EXPECT_EQ(
        r.drawCpuSkinned(CharacterId{}, crowd_.view(), crowd_.view().camera(), nullptr).code(),
        StatusCode::kUnsupported);
    r.setMotionVectors(false);
    EXPECT_FALSE(r.motionVectors());
    EXPECT_TRUE(
        r.drawCpuSkinned(CharacterId{}, crowd_.view(), crowd_.view().camera(), nullptr).isOk());
    r.shutdown();
  }
}

// A crowd without previous records cannot draw motion vectors: a named error, not garbage.
TEST_P(MotionVectorTest, NeedsTheCrowdsPreviousRecords) {
  Renderer r;
  makeMotionRenderer(&r);
  CrowdManager plain;
  makeOneInstanceCrowd(&plain);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  const Status s = r.drawCrowd(si::CharacterId{}, plain.view(), batcher, closeCamera(), nullptr);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  MotionTarget unmade;
  EXPECT_EQ(unmade.create(0, 16).code(), StatusCode::kInvalidArgument);
  std::vector<glm::vec2> motion;
  EXPECT_EQ(unmade.readMotion(&motion).code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("previous_records"), std::string::npos) << s.message();
  // Depth-only draws write no motion and need none.
  EXPECT_TRUE(r.drawCrowd(si::CharacterId{}, plain.view(), batcher, closeCamera(), nullptr,
                          DrawMode::kDepthOnly)
                  .isOk());
  r.shutdown();
}

// restore() binds what was bound before the target, however many frames cleared it (each
// clear() binds it again).
TEST_P(MotionVectorTest, RestoreBindsWhatWasBoundBeforeTheFirstClear) {
  MotionTarget target;
  ASSERT_TRUE(target.create(32, 16).isOk());
  GLint before = 0, viewport_before[4] = {};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &before);
  glGetIntegerv(GL_VIEWPORT, viewport_before);
  for (int frame = 0; frame < 2; ++frame) target.clear(glm::vec4(0.0f));
  GLint bound = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
  ASSERT_NE(bound, before);
  target.restore();
  GLint draw = 0, read = 0, viewport[4] = {};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
  glGetIntegerv(GL_VIEWPORT, viewport);
  EXPECT_EQ(draw, before);
  EXPECT_EQ(read, before);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(viewport[k], viewport_before[k]) << k;
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

// Frames that draw nothing (every instance behind the camera) after one that drew: no records
// and no previous indices, then no previous records either; both skinning paths draw them with
// motion vectors, no GL error.
TEST_P(MotionVectorTest, AnEmptyFrameDrawsWithMotionVectors) {
  for (SkinningPath path : {SkinningPath::kVertexShader, SkinningPath::kCompute}) {
    SCOPED_TRACE(skinningPathName(path));
    Renderer r;
    makeMotionRenderer(&r, path);
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
    ASSERT_TRUE(crowd_.update(0.05, camera(1)).isOk());
    ASSERT_TRUE(
        r.drawCrowd(CharacterId{}, crowd_.view(), batcher, crowd_.view().camera(), nullptr).isOk());
    const Camera away = Camera::lookAt({0.0, 1.6, 2.5}, {0.0, 1.6, 10.0}, glm::vec3(0, 1, 0), 0.9f,
                                       1.0f, 0.1f, 100.0f);
    ASSERT_TRUE(crowd_.update(0.05, away).isOk());
    ASSERT_TRUE(crowd_.view().records().empty());
    for (int frame = 0; frame < 2; ++frame) {  // Then no previous records either.
      DrawStats stats;
      const Status s = r.drawCrowd(CharacterId{}, crowd_.view(), batcher, away, &stats);
      EXPECT_TRUE(s.isOk()) << s.toString();
      EXPECT_EQ(stats.instances, 0u);
      EXPECT_TRUE(checkGlErrors("an empty frame with motion vectors").isOk());
      ASSERT_TRUE(crowd_.update(0.05, away).isOk());
    }
    EXPECT_TRUE(crowd_.view().previousRecords().empty());
    r.shutdown();
  }
}

// drawCrowd reads the previous records where its draw of the previous selection left them (no
// copy) while the ring holds that region: its motion equals that of a renderer that copies them
// (one ring region, which never holds the last draw), on both skinning paths, with a depth-only
// draw of the new selection between them, two instances placed anew (no previous record) and
// overlays on half of them (the compose pass reads the previous records too). With two draws
// between, the records are copied again.
TEST_P(MotionVectorTest, TheLastDrawsRegionServesAsThePreviousRecords) {
  LayerMask arm;
  ASSERT_TRUE(
      buildLayerMask(character().skeleton, palette(), "right arm", {"r_clavicle"}, &arm).isOk());
  uint32_t mask = 0;
  ASSERT_TRUE(crowd_.addLayerMask(arm, &mask).isOk());
  const uint32_t wave = uint32_t(palette().findClip("wave"));
  for (size_t k = 0; k < handles_.size(); k += 2)
    ASSERT_TRUE(crowd_.playOverlay(handles_[k], wave, mask, 0.7f, 0.0, 0.1 * double(k)).isOk());
  for (SkinningPath path : {SkinningPath::kVertexShader, SkinningPath::kCompute}) {
    SCOPED_TRACE(skinningPathName(path));
    Renderer reuse, copy;
    RendererDesc rd;
    rd.skinning_path = path;
    // Motion vectors from init(), or switched on later (the next drawCrowd sizes the ring).
    rd.motion_vectors = path == SkinningPath::kVertexShader;
    makeRenderer(&reuse, 0, PaletteFormat::kMatrix3x4F32, &rd);
    reuse.setMotionVectors(true);
    rd.motion_vectors = true;
    rd.ring_frames = 1;
    makeRenderer(&copy, 0, PaletteFormat::kMatrix3x4F32, &rd);
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(reuse.batchLimits()).isOk());
    const auto draw = [&](Renderer& r, DrawMode mode, std::vector<glm::vec2>* motion) {
      target_.clear(glm::vec4(0.0f));
      DrawStats stats;
      const Status s =
          r.drawCrowd(CharacterId{}, crowd_.view(), batcher, crowd_.view().camera(), &stats, mode);
      EXPECT_TRUE(s.isOk()) << s.toString();
      if (motion != nullptr) *motion = motions();
      return stats.previous_records_copied;
    };
    ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
    draw(reuse, DrawMode::kDefault, nullptr);
    draw(copy, DrawMode::kDefault, nullptr);
    for (size_t k : {5u, 10u}) {
      InstanceDesc d;
      ASSERT_TRUE(crowd_.get(handles_[k], &d).isOk());
      ASSERT_TRUE(crowd_.setTransform(handles_[k], d.position, d.rotation, d.scale).isOk());
    }
    nextFrame();
    const size_t previous = crowd_.view().previousRecords().size();
    ASSERT_GT(previous, 10u);
    std::vector<glm::vec2> read, copied;
    EXPECT_EQ(draw(reuse, DrawMode::kDepthOnly, nullptr), 0u);
    EXPECT_EQ(draw(reuse, DrawMode::kDefault, &read), 0u);
    EXPECT_EQ(draw(copy, DrawMode::kDefault, &copied), previous);
    EXPECT_FALSE(crowd_.view().previousLayerRecords().empty());
    float largest = 0.0f;
    for (const glm::vec2& m : copied) largest = std::max(largest, glm::length(m));
    EXPECT_GT(largest, 0.02f);
    EXPECT_TRUE(read == copied);
    // Two draws between: with the default 4 regions (motion vectors on), the region would be
    // written again right after the next draw, which would wait for this one: copied.
    nextFrame();
    for (int k = 0; k < 2; ++k) draw(reuse, DrawMode::kDepthOnly, nullptr);
    EXPECT_EQ(draw(reuse, DrawMode::kDefault, &read), crowd_.view().previousRecords().size());
    EXPECT_EQ(draw(copy, DrawMode::kDefault, &copied), crowd_.view().previousRecords().size());
    EXPECT_TRUE(read == copied);
    reuse.shutdown();
    copy.shutdown();
  }
}

// A drawCrowd that fails after planning its ring region (here: compute pre-skinning on a
// context whose compute grid is one group) leaves no note of where its records would have been: the
// view's next draw copies its previous records, and draws the motion of a renderer that always
// copies them, instead of reading the region another crowd's draw has written since as its own.
TEST_P(MotionVectorTest, AFailedDrawLeavesNoPreviousRecordsBehind) {
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.motion_vectors = true;
  GlInfo one_group = info_;  // Compute pre-skinning of an instance needs more groups.
  one_group.max_compute_groups_x = one_group.max_compute_groups_y = 1;
  Renderer r, copy;
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd, InterpolationChoice::kLinear, &one_group);
  rd.ring_frames = 1;  // Never holds the last draw's region: always copies.
  makeRenderer(&copy, 0, PaletteFormat::kMatrix3x4F32, &rd);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  CrowdManager other;
  CrowdDesc cd = crowd_.desc();
  ASSERT_TRUE(other.init(cd).isOk());
  for (int k = 0; k < 6; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3((k % 3 - 1) * 1.5, 0.0, -4.0 - 2.0 * (k / 3));
    d.time_seconds = 0.2 * k;
    InstanceHandle h;
    ASSERT_TRUE(other.add(d, &h).isOk());
  }
  ASSERT_TRUE(other.update(0.05, camera(1)).isOk());
  ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
  // The other crowd's draw, this crowd's refused one, the other's again (the same selection:
  // its note moves to the region the refused draw had planned).
  ASSERT_TRUE(r.drawCrowd(si::CharacterId{}, other.view(), batcher, camera(1), nullptr).isOk());
  const Status refused = r.drawCrowd(CharacterId{}, crowd_.view(), batcher, camera(1), nullptr,
                                     DrawMode::kComputeSkinned);
  EXPECT_EQ(refused.code(), StatusCode::kLimitExceeded) << refused.toString();
  ASSERT_TRUE(r.drawCrowd(si::CharacterId{}, other.view(), batcher, camera(1), nullptr).isOk());
  nextFrame();
  const size_t previous = crowd_.view().previousRecords().size();
  ASSERT_GT(previous, 10u);
  const auto motionOf = [&](Renderer& renderer, std::vector<glm::vec2>* motion) {
    target_.clear(glm::vec4(0.0f));
    DrawStats stats;
    const Status s =
        renderer.drawCrowd(CharacterId{}, crowd_.view(), batcher, crowd_.view().camera(), &stats);
    EXPECT_TRUE(s.isOk()) << s.toString();
    *motion = motions();
    return stats.previous_records_copied;
  };
  std::vector<glm::vec2> read, copied;
  EXPECT_EQ(motionOf(copy, &copied), previous);
  EXPECT_EQ(motionOf(r, &read), previous);
  float largest = 0.0f;
  for (const glm::vec2& m : copied) largest = std::max(largest, glm::length(m));
  EXPECT_GT(largest, 0.02f);
  expectMotionAgrees(copied, read);
  r.shutdown();
  copy.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, MotionVectorTest, allBackends(), backendTestName);

}  // namespace test
}  // namespace si
