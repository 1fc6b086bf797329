// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The instance handle in the surface (MaterialDesc::instance_handle): an object-id material
// reads each drawn instance's InstanceHandle::id on every path and on impostors; a material that
// does not ask reads 0.
#include <glad/gl.h>

#include <cmath>
#include <set>
#include <tuple>
#include <vector>

#include "render/host_material_fixture.h"

namespace si {
namespace {

using namespace test;

class InstanceHandleTest : public HostMaterialTest {};

// What kHandles drew into target 1 (`surface`) for `crowd` seen by `camera`: for each
// visible instance, the pixel at its middle (0.9 above its origin) where that pixel shows the
// instance's LOD (`impostors`: the impostor level), so no other instance covers it; `checked`
// of them, `wrong` showing another handle; `strays`: drawn pixels whose handle no visible
// instance has; `handles`: the distinct handles drawn.
struct HandleCheck {
  size_t checked = 0, wrong = 0, strays = 0, handles = 0;
};
HandleCheck checkHandles(const std::vector<uint8_t>& surface, const CrowdManager& crowd,
                         const Camera& camera, bool impostors) {
  const auto at = [&](size_t p) {
    return uint32_t(surface[p]) | uint32_t(surface[p + 1]) << 8 | uint32_t(surface[p + 2]) << 16;
  };
  std::set<uint32_t> visible, drawn;
  for (InstanceHandle h : crowd.view().visibleHandles()) visible.insert(h.id & 0xFFFFFFu);
  HandleCheck c;
  for (size_t p = 0; p < surface.size(); p += 4) {
    if (surface[p + 3] == 0) continue;
    drawn.insert(at(p));
    c.strays += visible.count(at(p)) == 0;
  }
  c.handles = drawn.size();
  for (InstanceHandle h : crowd.view().visibleHandles()) {
    InstanceDesc d;
    uint32_t lod = 0;
    if (!crowd.get(h, &d).isOk() || !crowd.view().lodOf(h, &lod).isOk()) continue;
    const glm::vec4 clip =
        camera.viewProjection() *
        glm::vec4(glm::vec3(d.position - camera.position) + glm::vec3(0, 0.9f, 0), 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    const int x = int((ndc.x * 0.5f + 0.5f) * kSize), y = int((ndc.y * 0.5f + 0.5f) * kSize);
    if (x < 0 || y < 0 || x >= int(kSize) || y >= int(kSize)) continue;
    const size_t p = (size_t(y) * kSize + size_t(x)) * 4;
    const uint8_t alpha = impostors ? 255 : uint8_t(std::lround((lod + 1) * 255.0 / 8.0));
    if (surface[p + 3] != alpha) continue;  // Background, or another instance in front.
    ++c.checked;
    c.wrong += at(p) != (h.id & 0xFFFFFFu);
  }
  return c;
}

// A material that asks for the instance handle (MaterialDesc::instance_handle) reads each
// drawn instance's InstanceHandle::id on every path (its low 24 bits in target 1's colour:
// every instance's own at its middle, the same images on every path); a material that does not
// ask reads 0.
constexpr const char* kHandles = R"(
layout(location = 0) out vec4 o_lit;
layout(location = 1) out vec4 o_surface;
void siMaterial(SiSurface s) {
  o_lit = vec4(s.instance == 0u ? 1.0 : 0.0, 0.0, 0.0, 1.0);
  o_surface = vec4(unpackUnorm4x8(s.instance).rgb, s.impostor ? 1.0 : float(s.lod + 1u) / 8.0);
})";

TEST_P(InstanceHandleTest, TheInstanceHandleReachesTheMaterialOnEveryPath) {
  TwoTargets targets(kSize);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.3, lodCamera()).isOk());
  Renderer vs, cs, unasked;
  makeMaterialRenderer(&vs, SkinningPath::kVertexShader, nullptr, false, kHandles, true);
  makeMaterialRenderer(&cs, SkinningPath::kCompute, nullptr, false, kHandles, true);
  std::vector<uint8_t> lit, surface;
  std::tie(lit, surface) = expectTheSameImagesOnEveryPath(vs, cs, crowd, targets, lodCamera());
  const HandleCheck c = checkHandles(surface, crowd, lodCamera(), false);
  EXPECT_GE(c.checked, 16u);
  EXPECT_EQ(c.wrong, 0u);
  EXPECT_EQ(c.strays, 0u);
  EXPECT_GE(c.handles, 20u) << "of " << crowd.view().visibleHandles().size() << " visible";
  size_t null_handles = 0;
  for (size_t p = 0; p < lit.size(); p += 4) null_handles += surface[p + 3] != 0 && lit[p] != 0;
  EXPECT_EQ(null_handles, 0u);
  // Without instance_handle the material reads the null handle.
  makeMaterialRenderer(&unasked, SkinningPath::kVertexShader, nullptr, false, kHandles, false);
  drawInto(unasked, PathKind::kInstanced, crowd, targets);
  const std::vector<uint8_t> unasked_lit = targets.read(0), unasked_surface = targets.read(1);
  size_t drawn = 0, not_null = 0;
  for (size_t p = 0; p < lit.size(); p += 4) {
    if (unasked_surface[p + 3] == 0) continue;
    ++drawn;
    not_null += unasked_lit[p] != 255 || unasked_surface[p] != 0 || unasked_surface[p + 1] != 0 ||
                unasked_surface[p + 2] != 0;
  }
  EXPECT_GT(drawn, 2000u);
  EXPECT_EQ(not_null, 0u);
}

// The same on impostors, instanced and GPU-driven: one row of 8 at the impostor level.
TEST_P(InstanceHandleTest, TheInstanceHandleReachesTheMaterialOnImpostors) {
  TwoTargets targets(kSize);
  CrowdManager crowd;
  impostorRowsCrowd(3.0, 30.0, 20.0, &crowd);
  const std::vector<InstanceHandle> all(crowd.view().visibleHandles().begin(),
                                        crowd.view().visibleHandles().end());
  for (InstanceHandle h : all) {  // The second row goes: nothing stands behind the first.
    InstanceDesc d;
    ASSERT_TRUE(crowd.get(h, &d).isOk());
    if (d.position.z < -40.0) {
      ASSERT_TRUE(crowd.remove(h).isOk());
    }
  }
  ASSERT_TRUE(crowd.update(0.2, lodCamera()).isOk());
  ASSERT_EQ(crowd.view().visibleHandles().size(), 8u);
  Renderer r;
  makeMaterialRenderer(&r, SkinningPath::kVertexShader, &impostorCharacter(), false, kHandles,
                       true);
  ImpostorDesc id;
  id.azimuths = 8;
  id.frames_per_clip = 4;
  ASSERT_TRUE(r.buildImpostor(CharacterId{}, id).isOk());
  for (PathKind kind : {PathKind::kInstanced, PathKind::kGpuDriven}) {
    SCOPED_TRACE(kind == PathKind::kInstanced ? "instanced" : "gpu-driven");
    drawInto(r, kind, crowd, targets);
    const HandleCheck c = checkHandles(targets.read(1), crowd, lodCamera(), true);
    EXPECT_GE(c.checked, 6u);
    EXPECT_EQ(c.wrong, 0u);
    EXPECT_EQ(c.strays, 0u);
    EXPECT_EQ(c.handles, 8u);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, InstanceHandleTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
