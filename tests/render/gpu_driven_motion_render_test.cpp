// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Motion vectors on the GPU-driven path: the records it drew kept on the GPU per handle, the
// fallback for another crowd, and draws without motion vectors leaving its frame alone.
// MotionVectorTest's instantiation (motion_vectors_render_test.cpp) runs these too.
#include "gl/paths/gpu_culled_crowds.h"
#include "render/motion_vector_fixture.h"

namespace si {
namespace test {

// The GPU-driven path keeps what it drew: its motion, with both of its draws and with occlusion
// culling, equals the engine program's across the same crossfades, cut and speed change (the
// crowd's previous records are not used: it draws the crowd's clock with the draw camera, which
// here is the update camera). With jittered draw cameras, setGpuMotionProjection keeps the
// jitter out of the motion; without it, the jitter shows.
TEST_P(MotionVectorTest, TheGpuDrivenPathKeepsWhatItDrew) {
  // Jitter: each frame's draw camera is moved by a different part of a pixel (as temporal
  // anti-aliasing does); setGpuMotionProjection gives the unjittered projection for the motion.
  enum class Jitter { kNone, kUnjitteredMotion, kInMotion };
  struct Variant {
    DrawMode mode;
    bool occlusion;
    Jitter jitter;
    std::unique_ptr<Renderer> renderer;
  };
  std::vector<Variant> variants;
  const auto add = [&](DrawMode mode, bool occlusion, Jitter jitter) {
    RendererDesc rd;
    rd.motion_vectors = true;
    rd.gpu_occlusion_culling = occlusion;
    rd.gpu_driven_ring_bytes = 4u << 20;  // Plenty for 16 instances.
    rd.skinning_path = SkinningPath::kVertexShader;  // The draws name their mode: no timing.
    variants.push_back({mode, occlusion, jitter, std::make_unique<Renderer>()});
    makeRenderer(variants.back().renderer.get(), 0, PaletteFormat::kMatrix3x4F32, &rd);
  };
  for (const bool occlusion : {false, true})
    for (const DrawMode mode : {DrawMode::kSkinned, DrawMode::kComputeSkinned})
      add(mode, occlusion, Jitter::kNone);
  add(DrawMode::kComputeSkinned, false, Jitter::kUnjitteredMotion);
  add(DrawMode::kSkinned, false, Jitter::kInMotion);
  const auto draw = [&](Variant& v, int frame) {
    Camera c = camera(frame);
    if (v.jitter == Jitter::kNone) {
      ASSERT_TRUE(
          v.renderer->drawCrowdGpuCulled(CharacterId{}, crowd_.view(), c, nullptr, v.mode).isOk());
      return;
    }
    const glm::mat4 unjittered = c.projection;
    const float px = 2.0f / float(kSize);  // One pixel in normalized device coordinates.
    const glm::vec3 shift = frame == 1 ? glm::vec3(0.4f * px, -0.3f * px, 0.0f)
                                       : glm::vec3(-0.35f * px, 0.25f * px, 0.0f);
    c.projection = glm::translate(glm::mat4(1.0f), shift) * c.projection;
    v.renderer->setGpuMotionProjection(v.jitter == Jitter::kUnjitteredMotion ? &unjittered
                                                                             : nullptr);
    ASSERT_TRUE(
        v.renderer->drawCrowdGpuCulled(CharacterId{}, crowd_.view(), c, nullptr, v.mode).isOk());
  };
  // Frame N, drawn at its clock with its camera by every variant; then frame N+1.
  ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
  for (Variant& v : variants) {
    target_.clear(glm::vec4(0.0f));
    draw(v, 1);
  }
  nextFrame();
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<glm::vec2> expected = motions();
  const std::vector<float> expected_depth = depths();
  for (Variant& v : variants) {
    SCOPED_TRACE(std::string(v.mode == DrawMode::kSkinned ? "vertex shader" : "pre-skinned") +
                 (v.occlusion ? ", occlusion culling" : "") +
                 (v.jitter == Jitter::kUnjitteredMotion ? ", jittered"
                  : v.jitter == Jitter::kInMotion       ? ", jitter in the motion"
                                                        : ""));
    target_.clear(glm::vec4(0.0f));
    draw(v, 2);
    const std::vector<glm::vec2> motion = motions();
    const std::vector<float> depth = depths();
    // A jittered pixel shows a point of the surface up to half a pixel away: its motion is
    // compared with the closest expected motion of the pixel's 3x3 neighbourhood, to 1e-3 (0.26
    // pixels). The jitter itself moves the image 0.93 pixels (3.6e-3) between the frames.
    const int reach = v.jitter == Jitter::kNone ? 0 : 1;
    size_t compared = 0, within = 0;
    double worst = 0.0;
    for (size_t p = 0; p < motion.size(); ++p) {
      if (depth[p] >= 1.0f || expected_depth[p] >= 1.0f) continue;
      ++compared;
      const int x = int(p % kSize), y = int(p / kSize);
      double off = 1e30;
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= int(kSize) || qy >= int(kSize)) continue;
          const size_t q = size_t(qy) * kSize + size_t(qx);
          if (expected_depth[q] < 1.0f)
            off = std::min(off, double(glm::length(motion[p] - expected[q])));
        }
      within += off <= (reach == 0 ? 1e-4 : 1e-3);
      worst = std::max(worst, off);
    }
    EXPECT_GT(compared, size_t(kSize) * kSize / 10);
    // Measured: every pixel without jitter; 99.4 % with the unjittered motion projection (the
    // rest where the jitter shows another instance); 0.04 % with the jitter in the motion.
    if (v.jitter == Jitter::kInMotion)
      EXPECT_LT(double(within), 0.01 * double(compared));
    else
      EXPECT_GE(double(within), (reach == 0 ? 0.995 : 0.99) * double(compared)) << "worst " << worst;
  }
  for (Variant& v : variants) v.renderer->shutdown();
}

// What the GPU-driven path drew belongs to its crowd: a crowd re-initialized in place with the
// same handles, drawn at the next clock, gets the fallback (still camera: no motion), not the
// old crowd's records.
TEST_P(MotionVectorTest, AnotherCrowdStartsOverOnTheGpuDrivenPath) {
  Renderer r;
  makeMotionRenderer(&r);
  const auto populate = [&](double x) {
    CrowdDesc cd = crowd_.desc();
    ASSERT_TRUE(crowd_.init(cd).isOk());
    for (int k = 0; k < 8; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3(x + (k % 4 - 1.5) * 1.3, 0.0, -3.0 - 1.6 * (k / 4));
      d.clip = uint32_t(palette().findClip("walk"));
      d.time_seconds = 0.2 * k;
      InstanceHandle h;
      ASSERT_TRUE(crowd_.add(d, &h).isOk());
    }
  };
  populate(0.0);
  ASSERT_TRUE(
      r.drawCrowdGpuCulled(CharacterId{}, crowd_.view(), camera(1), nullptr, DrawMode::kSkinned)
          .isOk());
  const uint64_t first = crowd_.identity();
  populate(0.4);  // Same handles, other places and clock 0 again: then the next clock.
  ASSERT_NE(crowd_.identity(), first);
  ASSERT_TRUE(crowd_.advance(1.0 / 30.0).isOk());
  target_.clear(glm::vec4(0.0f));
  ASSERT_TRUE(
      r.drawCrowdGpuCulled(CharacterId{}, crowd_.view(), camera(1), nullptr, DrawMode::kSkinned)
          .isOk());
  MotionSummary summary;
  ASSERT_TRUE(target_.summarize(&summary).isOk());
  EXPECT_GT(summary.drawn_pixels, size_t(kSize) * kSize / 20);
  EXPECT_LT(summary.max_pixels, 1e-3);
  // The same crowd's next frame moves (the clips play).
  ASSERT_TRUE(crowd_.advance(1.0 / 30.0).isOk());
  target_.clear(glm::vec4(0.0f));
  ASSERT_TRUE(
      r.drawCrowdGpuCulled(CharacterId{}, crowd_.view(), camera(1), nullptr, DrawMode::kSkinned)
          .isOk());
  ASSERT_TRUE(target_.summarize(&summary).isOk());
  EXPECT_GT(summary.max_pixels, 0.5);
  r.shutdown();
}

// Several crowds of one character keep their own GPU-driven state: drawn in turn, an unchanged
// crowd uploads nothing again, and each keeps what it drew (its motion equals the engine
// program's, not the fallback's).
TEST_P(MotionVectorTest, SeveralCrowdsOfOneCharacterKeepTheirOwnState) {
  Renderer r;
  makeMotionRenderer(&r);
  CrowdManager other;
  ASSERT_TRUE(other.init(crowd_.desc()).isOk());
  for (int k = 0; k < 8; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3(-2.0 + 0.6 * k, 0.0, -12.0);
    d.clip = uint32_t(palette().findClip("walk"));
    InstanceHandle h;
    ASSERT_TRUE(other.add(d, &h).isOk());
  }
  DrawStats stats;
  for (int frame = 1; frame <= 2; ++frame) {
    if (frame == 2)
      nextFrame();
    else
      ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
    ASSERT_TRUE(other.update(1.0 / 30.0, camera(frame)).isOk());
    ASSERT_TRUE(r.drawCrowdGpuCulled(si::CharacterId{}, other.view(), camera(frame), &stats,
                                     DrawMode::kSkinned)
                    .isOk());
    if (frame == 2) {
      EXPECT_EQ(stats.state_bytes_uploaded, 0u) << "the other crowd uploaded again";
    }
    target_.clear(glm::vec4(0.0f));
    ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd_.view(), camera(frame), &stats,
                                     DrawMode::kSkinned)
                    .isOk());
  }
  const std::vector<glm::vec2> motion = motions();
  const std::vector<float> depth = depths();
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<glm::vec2> expected = motions();
  const std::vector<float> expected_depth = depths();
  const std::vector<uint8_t> expected_color = colors();
  expectMotion(motion, depth, expected, expected_depth, expected_color);
  r.shutdown();
}

// Past GpuCulledCrowds::kMaxCrowds crowds of one character, the least recently drawn loses its
// state (its next draw uploads it whole); the others keep theirs; and a crowd not drawn for
// kIdleDraws draws of the character loses its own.
TEST_P(MotionVectorTest, TheLeastRecentlyDrawnCrowdGoesPastTheCount) {
  Renderer r;
  makeMotionRenderer(&r);
  std::vector<CrowdManager> crowds(detail::GpuCulledCrowds::kMaxCrowds + 1);
  for (CrowdManager& c : crowds) {
    ASSERT_TRUE(c.init(crowd_.desc()).isOk());
    InstanceHandle h;
    ASSERT_TRUE(c.add(InstanceDesc(), &h).isOk());
    ASSERT_TRUE(c.advance(0.0).isOk());
  }
  DrawStats stats;
  const auto uploaded = [&](CrowdManager& c) {
    EXPECT_TRUE(
        r.drawCrowdGpuCulled(si::CharacterId{}, c.view(), camera(1), &stats, DrawMode::kSkinned)
            .isOk());
    return stats.state_bytes_uploaded;
  };
  for (CrowdManager& c : crowds) EXPECT_EQ(uploaded(c), sizeof(GpuInstanceState));
  EXPECT_EQ(uploaded(crowds.back()), 0u);  // Kept.
  EXPECT_EQ(uploaded(crowds[1]), 0u);      // Kept: crowds[0] went for the last one.
  EXPECT_EQ(uploaded(crowds[0]), sizeof(GpuInstanceState));
  // A crowd no longer drawn (destroyed, say) frees its state within kIdleDraws draws of the
  // character, though no other crowd comes. 4097 draws: 23 s under the sanitizers, so on one
  // back-end (the eviction is not the driver's).
  if (GetParam() == HeadlessBackend::kOsMesa) {
    r.shutdown();
    return;
  }
  for (uint64_t k = 0; k <= detail::GpuCulledCrowds::kIdleDraws; ++k) (void)uploaded(crowds[0]);
  GpuMemory m;
  ASSERT_TRUE(r.gpuMemory(&m).isOk());
  ASSERT_EQ(m.characters[0].crowds.size(), 1u);
  EXPECT_EQ(m.characters[0].crowds[0].crowd, crowds[0].identity());
  r.shutdown();
}

// A GPU-driven draw without motion vectors (a shadow view) at a frame's clock changes neither
// that frame's camera nor what was drawn: the next frame's motion is the one without it.
TEST_P(MotionVectorTest, ADrawWithoutMotionLeavesTheGpuDrivenFrameAlone) {
  Renderer plain, shadowed;
  makeMotionRenderer(&plain);
  makeMotionRenderer(&shadowed);
  const Camera shadow = Camera::lookAt({6.0, 9.0, -4.0}, {0.0, 0.0, -5.0}, glm::vec3(0, 1, 0),
                                       0.9f, 1.0f, 0.1f, 100.0f);
  std::vector<glm::vec2> motion[2];
  std::vector<float> depth[2];
  for (int frame = 1; frame <= 2; ++frame) {
    if (frame == 2) nextFrame();
    else ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
    for (int k = 0; k < 2; ++k) {
      Renderer& r = k == 0 ? plain : shadowed;
      target_.clear(glm::vec4(0.0f));
      ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd_.view(), camera(frame), nullptr,
                                       DrawMode::kSkinned)
                      .isOk());
      if (frame == 2) motion[k] = motions(), depth[k] = depths();
      if (k == 1) {  // The shadow view, after the frame's motion draw.
        r.setMotionVectors(false);
        ASSERT_TRUE(
            r.drawCrowdGpuCulled(CharacterId{}, crowd_.view(), shadow, nullptr, DrawMode::kSkinned)
                .isOk());
        r.setMotionVectors(true);
      }
    }
  }
  // Both equal the engine program's motion from the crowd's records (as
  // TheGpuDrivenPathKeepsWhatItDrew checks), so neither took the shadow view as its camera.
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<glm::vec2> expected = motions();
  const std::vector<float> expected_depth = depths();
  const std::vector<uint8_t> expected_color = colors();  // Each instance's flat tint.
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k == 0 ? "without the shadow view" : "with the shadow view");
    expectMotion(motion[k], depth[k], expected, expected_depth, expected_color);
  }
  plain.shutdown();
  shadowed.shutdown();
}

}  // namespace test
}  // namespace si
