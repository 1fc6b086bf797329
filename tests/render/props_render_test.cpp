// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Sockets and props, the GL half: a box held at the right hand's grip (si::attachProp), shown
// by two thirds of a walking crowd (its variation bit), some crossfading, some waving the arm
// that holds it (an overlay), some blending the walk and the run (a blend space), is drawn by
// every path as the CPU emulation draws it; the prop shows; drawn alone it lies where
// CrowdManager::socketTransform says.
#include <cmath>
#include <cstring>

#include "core/prop_fixture.h"
#include "render/render_fixture.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/motion_target.h"

namespace si {
namespace {

using namespace test;

class PropsRenderTest : public RenderTest {
 protected:
  static constexpr glm::vec3 kHalf{0.03f, 0.05f, 0.35f};  // The box's half extents.
  void SetUp() override {
    RenderTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    held_ = character();
    ASSERT_TRUE(makeSocket(held_.skeleton, "grip", "r_hand", gripOffset(), &grip_).isOk());
    ASSERT_TRUE(attachProp(grip_, boxProp(kHalf), &held_, &prop_bit_).isOk());
  }
  // A renderer of the character holding the prop (the default palette stores the hand).
  void makePropRenderer(Renderer* r, SkinningPath path = SkinningPath::kVertexShader) {
    RendererDesc rd;
    rd.skinning_path = path;
    rd.measure_gpu_time = true;
    ASSERT_TRUE(r->init(info_, rd).isOk());
    CharacterId id;
    const Status s = r->addCharacter(held_, palette(), &id);
    ASSERT_TRUE(s.isOk()) << s.toString();
  }
  // 12 instances walking; two thirds hold the prop, a third crossfades into the run, a quarter
  // wave the arm that holds it, a quarter blend the walk and the run.
  void populate(CrowdManager* crowd) {
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = uint32_t(held_.mesh.sub_meshes.size());
    cd.lod_count = 3;
    ASSERT_TRUE(crowd->init(cd).isOk());
    LayerMask arm;
    ASSERT_TRUE(buildLayerMask(held_.skeleton, palette(), "arm", {"r_clavicle"}, &arm).isOk());
    uint32_t mask = 0, body_mask = 0, locomotion = 0;
    ASSERT_TRUE(crowd->addLayerMask(arm, &mask).isOk());
    LayerMask body;
    ASSERT_TRUE(buildFullBodyMask(held_.skeleton, palette(), "body", &body).isOk());
    ASSERT_TRUE(crowd->addLayerMask(body, &body_mask).isOk());
    const uint32_t walk = uint32_t(palette().findClip("walk")),
                   run = uint32_t(palette().findClip("run"));
    const uint32_t wave = uint32_t(palette().findClip("wave"));
    ASSERT_TRUE(
        crowd->addBlendSpace({"locomotion", {walk, run}, {0.0f, 1.0f}, body_mask}, &locomotion)
            .isOk());
    for (int k = 0; k < 12; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k % 4 - 1.5) * 1.2, 0.0, -2.5 - 1.5 * (k / 4));
      d.rotation = glm::angleAxis(0.6f * float(k % 3 - 1) - 0.5f, glm::vec3(0, 1, 0));
      d.clip = walk;
      d.time_seconds = 0.13 * k;
      d.variation_mask = k % 3 == 2 ? 0x1u : 0x1u | (1u << prop_bit_);
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
      handles_.push_back(h);
      if (k % 3 == 1) {
        ASSERT_TRUE(crowd->crossfade(h, run, 1.0).isOk());
      }
      if (k % 4 == 0) {
        ASSERT_TRUE(crowd->playOverlay(h, wave, mask, 1.0f, 0.0, 0.1 * k).isOk());
      } else if (k % 4 == 2) {  // Blending the walk and the run (a blend space), some fading in.
        ASSERT_TRUE(
            crowd->playBlend(h, locomotion, 0.2f * float(k % 5), k % 3 == 0 ? 0.0 : 1.0, 0.07 * k)
                .isOk());
      }
    }
    ASSERT_TRUE(crowd->update(0.4, view()).isOk());
  }
  static Camera view() {
    return Camera::lookAt({0.0, 1.6, 2.5}, {0.0, 1.0, -4.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                          100.0f);
  }
  Character held_;
  Socket grip_;
  uint32_t prop_bit_ = 0;
  std::vector<InstanceHandle> handles_;
};

TEST_P(PropsRenderTest, EveryPathDrawsTheEmulatedProps) {
  Renderer r, pre;
  makePropRenderer(&r);
  makePropRenderer(&pre, SkinningPath::kCompute);
  CrowdManager crowd;
  populate(&crowd);
  DrawStats cpu_stats;
  const std::vector<uint8_t> cpu = draw(r, crowd, view(), 0, false, &cpu_stats, Path::kCpuSkinned);
  expectEveryCaseDraws(
      {{"vertex shader", &r, Path::kInstanced, false, DrawMode::kSkinned},
       {"compute", &pre, Path::kCompute, false, DrawMode::kComputeSkinned},
       {"gpu-driven", &r, Path::kInstanced, true, DrawMode::kSkinned},
       {"gpu-driven pre-skinned", &r, Path::kInstanced, true, DrawMode::kComputeSkinned}},
      crowd, view(), cpu, cpu_stats);
  // The props show: without them (every variation bit but the body's off) the image differs.
  for (InstanceHandle h : handles_) ASSERT_TRUE(crowd.setVariationMask(h, 0x1u).isOk());
  ASSERT_TRUE(crowd.update(0.0, view()).isOk());
  const std::vector<uint8_t> bare = draw(r, crowd, view(), 0);
  EXPECT_GT(compare(bare, cpu, nullptr).share, 0.003);
  r.shutdown();
  pre.shutdown();
}

// Drawn alone (the body's bit off), each prop covers the box its corners, placed by
// CrowdManager::socketTransform, project to.
TEST_P(PropsRenderTest, ThePropIsDrawnWhereTheSocketSays) {
  Renderer r;
  makePropRenderer(&r);
  CrowdManager crowd;
  populate(&crowd);
  const Camera camera = view();
  for (InstanceHandle h : handles_) ASSERT_TRUE(crowd.setVariationMask(h, 0u).isOk());
  ASSERT_TRUE(crowd.update(0.0, camera).isOk());
  const std::vector<uint8_t> empty = draw(r, crowd, camera, 0);
  int checked = 0;
  for (size_t k = 0; k < handles_.size(); ++k) {
    SCOPED_TRACE(k);
    // This instance's prop only.
    for (size_t j = 0; j < handles_.size(); ++j)
      ASSERT_TRUE(crowd.setVariationMask(handles_[j], j == k ? 1u << prop_bit_ : 0u).isOk());
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    const std::vector<uint8_t> image = draw(r, crowd, camera, 0);
    // The drawn pixels' box and the box of the prop's eight corners projected through
    // socketTransform (a convex solid covers exactly its corners' projected hull).
    glm::dvec2 lo(1e9), hi(-1e9);
    int count = 0;
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        const size_t at = (size_t(y) * kSize + x) * 4;
        if (std::memcmp(&image[at], &empty[at], 3) == 0) continue;
        lo = glm::min(lo, glm::dvec2(x, y));
        hi = glm::max(hi, glm::dvec2(x + 1.0, y + 1.0));
        ++count;
      }
    glm::dmat4 socket;
    ASSERT_TRUE(crowd.socketTransform(handles_[k], grip_, &socket).isOk());
    glm::dvec2 plo(1e9), phi(-1e9);
    bool inside = true;
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 corner(c & 1 ? kHalf.x : -kHalf.x, c & 2 ? kHalf.y : -kHalf.y,
                              c & 4 ? 2.0 * kHalf.z : 0.0);
      const glm::dvec3 world(socket * glm::dvec4(corner, 1.0));
      const glm::dvec4 clip =
          glm::dmat4(camera.viewProjection()) * glm::dvec4(world - camera.position, 1.0);
      const glm::dvec2 pixel((clip.x / clip.w * 0.5 + 0.5) * kSize,
                             (0.5 - clip.y / clip.w * 0.5) * kSize);
      inside = inside && clip.w > 0.0 && pixel.x > 0.0 && pixel.y > 0.0 && pixel.x < kSize &&
               pixel.y < kSize;
      plo = glm::min(plo, pixel);
      phi = glm::max(phi, pixel);
    }
    if (!inside || count < 20) continue;  // Off screen (or its edge), or hidden.
    EXPECT_LT(glm::length(lo - plo), 1.5) << count << " pixels";
    EXPECT_LT(glm::length(hi - phi), 1.5) << count << " pixels";
    ++checked;
  }
  EXPECT_GE(checked, 6);
  r.shutdown();
}

// Motion vectors of a prop held by a character moving through a blend (walking, the parameter
// moving from the walk towards the run between the frames): every path writes the same motion,
// and over the prop's pixels it averages the motion of the box's centre placed by
// socketTransform in each frame (a rigid box moving a few pixels: its pixels move as its centre
// does, within a quarter of a pixel).
TEST_P(PropsRenderTest, PropsOfBlendingCharactersMoveAsTheirSocketsSay) {
  RendererDesc rd;
  rd.motion_vectors = true;
  rd.gpu_driven_ring_bytes = 4u << 20;
  rd.skinning_path = SkinningPath::kVertexShader;
  Renderer r;
  ASSERT_TRUE(r.init(info_, rd).isOk());
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(held_, palette(), &id).isOk());
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  MotionTarget target;
  ASSERT_TRUE(target.create(kSize, kSize).isOk());
  const Camera camera = view();
  glm::dvec2 expected(0.0);
  const auto motionOf = [&](DrawMode mode, bool gpu_driven, std::vector<glm::vec2>* motion,
                            std::vector<uint8_t>* color) {
    CrowdManager crowd;
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = uint32_t(held_.mesh.sub_meshes.size());
    cd.lod_count = 1;
    cd.previous_records = true;
    ASSERT_TRUE(crowd.init(cd).isOk());
    LayerMask body;
    ASSERT_TRUE(buildFullBodyMask(held_.skeleton, palette(), "body", &body).isOk());
    uint32_t mask = 0, space = 0;
    ASSERT_TRUE(crowd.addLayerMask(body, &mask).isOk());
    const uint32_t walk = uint32_t(palette().findClip("walk")),
                   run = uint32_t(palette().findClip("run"));
    ASSERT_TRUE(
        crowd.addBlendSpace({"locomotion", {walk, run}, {0.0f, 1.0f}, mask}, &space).isOk());
    InstanceDesc d;
    d.position = glm::dvec3(0.3, 0.0, -2.8);
    d.rotation = glm::angleAxis(-1.2f, glm::vec3(0, 1, 0));  // The right hand towards the camera.
    d.variation_mask = 1u << prop_bit_;                      // The prop alone.
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    ASSERT_TRUE(crowd.playBlend(h, space, 0.2f, 0.0, 0.3).isOk());
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    glm::dmat4 before, after;
    ASSERT_TRUE(crowd.socketTransform(h, grip_, &before).isOk());
    if (gpu_driven) {
      ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, nullptr, mode).isOk());
    }
    ASSERT_TRUE(crowd.setBlendParameter(h, 0.35f).isOk());
    if (gpu_driven) {
      ASSERT_TRUE(crowd.advance(0.05).isOk());
    } else {
      ASSERT_TRUE(crowd.update(0.05, camera).isOk());
    }
    ASSERT_TRUE(crowd.socketTransform(h, grip_, &after).isOk());
    target.clear(glm::vec4(0.0f));
    const Status s = gpu_driven
                         ? r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, nullptr, mode)
                         : r.drawCrowd(CharacterId{}, crowd.view(), batcher, camera, nullptr, mode);
    ASSERT_TRUE(s.isOk()) << s.toString();
    ASSERT_TRUE(target.readMotion(motion).isOk());
    ASSERT_TRUE(target.readColor(color).isOk());
    // Texture coordinates of the box's centre in each frame (bottom row up, as readMotion).
    const auto uv = [&](const glm::dmat4& m) {
      const glm::dvec3 c(m * glm::dvec4(0.0, 0.0, kHalf.z, 1.0));
      const glm::dvec4 clip =
          glm::dmat4(camera.viewProjection()) * glm::dvec4(c - camera.position, 1.0);
      return glm::dvec2(clip.x / clip.w, clip.y / clip.w) * 0.5 + 0.5;
    };
    expected = uv(after) - uv(before);
  };
  std::vector<glm::vec2> vs, cs, gpu_vs, gpu_cs;
  std::vector<uint8_t> color, unused;
  motionOf(DrawMode::kSkinned, false, &vs, &color);
  motionOf(DrawMode::kComputeSkinned, false, &cs, &unused);
  motionOf(DrawMode::kSkinned, true, &gpu_vs, &unused);
  motionOf(DrawMode::kComputeSkinned, true, &gpu_cs, &unused);
  glm::dvec2 mean(0.0);
  size_t covered = 0;
  for (size_t i = 0; i < vs.size(); ++i) {
    if (color[i * 4 + 3] == 0) continue;  // Nothing drawn (cleared to 0).
    mean += glm::dvec2(vs[i]);
    ++covered;
  }
  ASSERT_GT(covered, 30u);
  mean /= double(covered);
  std::printf(
      "[ props    ] %zu prop pixels: mean motion (%.2f, %.2f) px, the socket's (%.2f, %.2f) px\n",
      covered, mean.x * kSize, mean.y * kSize, expected.x * kSize, expected.y * kSize);
  EXPECT_GT(glm::length(expected) * kSize, 1.0);  // It moves.
  EXPECT_LT(glm::length(mean - expected) * kSize, 0.25);
  for (const std::vector<glm::vec2>* other : {&cs, &gpu_vs, &gpu_cs}) {
    SCOPED_TRACE(other - &vs);
    expectMotionAgrees(vs, *other);
  }
  target.restore();
  target.release();
  r.shutdown();
}

// Depth-only draws (shadow maps) of the blending, prop-holding crowd write the depth the colour
// draw writes, on drawCrowd's path and the GPU-driven one; without the blends and props the
// depth differs.
TEST_P(PropsRenderTest, DepthOnlyDrawsTheBlendedPropHolders) {
  Renderer r;
  makePropRenderer(&r);
  CrowdManager crowd;
  populate(&crowd);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  MotionTarget target;
  ASSERT_TRUE(target.create(kSize, kSize).isOk());
  const auto depthOf = [&](DrawMode mode, bool gpu_driven) {
    target.clear(glm::vec4(0.0f));
    const Status s = gpu_driven
                         ? r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), view(), nullptr, mode)
                         : r.drawCrowd(CharacterId{}, crowd.view(), batcher, view(), nullptr, mode);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<float> depth;
    EXPECT_TRUE(target.readDepth(&depth).isOk());
    return depth;
  };
  const std::vector<float> colour = depthOf(DrawMode::kSkinned, false);
  ASSERT_EQ(colour.size(), size_t(kSize) * kSize);
  EXPECT_EQ(differingDepths(colour, depthOf(DrawMode::kDepthOnly, false)), 0u);
  EXPECT_LE(differingDepths(colour, depthOf(DrawMode::kDepthOnly, true)), colour.size() / 1000);
  // Without: every instance back on its plain walk, the body alone.
  const uint32_t walk = uint32_t(palette().findClip("walk"));
  for (InstanceHandle h : handles_) {
    ASSERT_TRUE(crowd.play(h, walk, 0.0, 1.0f).isOk());
    ASSERT_TRUE(crowd.setVariationMask(h, 0x1u).isOk());
  }
  ASSERT_TRUE(crowd.update(0.0, view()).isOk());
  EXPECT_GT(differingDepths(colour, depthOf(DrawMode::kDepthOnly, false)), colour.size() / 100);
  target.restore();
  target.release();
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, PropsRenderTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
