// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Sockets and props, the GL half: a box held at the right hand's grip (si::attachProp), shown
// by two thirds of a walking crowd (its variation bit), some crossfading, some waving the arm
// that holds it (an overlay), is drawn by every path as the CPU emulation draws it; the prop
// shows; drawn alone it lies where CrowdManager::socketTransform says.
#include <cstring>

#include "core/prop_fixture.h"
#include "render/render_fixture.h"

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
  // wave the arm that holds it.
  void populate(CrowdManager* crowd) {
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = uint32_t(held_.mesh.sub_meshes.size());
    cd.lod_count = 3;
    ASSERT_TRUE(crowd->init(cd).isOk());
    LayerMask arm;
    ASSERT_TRUE(buildLayerMask(held_.skeleton, palette(), "arm", {"r_clavicle"}, &arm).isOk());
    uint32_t mask = 0;
    ASSERT_TRUE(crowd->addLayerMask(arm, &mask).isOk());
    const uint32_t walk = uint32_t(palette().findClip("walk")),
                   run = uint32_t(palette().findClip("run"));
    const uint32_t wave = uint32_t(palette().findClip("wave"));
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

INSTANTIATE_TEST_SUITE_P(Backends, PropsRenderTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
