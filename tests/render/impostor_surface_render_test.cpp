// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// An impostor atlas whose surface layer holds one value (ImpostorInfo::uniform_surface): the
// impostor fragments hand the material that value, exactly, on the instanced and GPU-driven
// paths; an atlas of two materials reads its layer, and each material's pixels keep theirs.
#include <glad/gl.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "render/impostor_fixture.h"
#include "render/pbr_probe.h"
#include "render/two_targets.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using namespace test;

constexpr float kMetallic[2] = {0.4f, 0.9f}, kRoughness[2] = {0.6f, 0.2f};

// impostorCharacter() in material 0 (metallic 0.4, roughness 0.6, no image); with `two`, its
// sub-mesh 0 in material 1 (metallic 0.9, roughness 0.2).
Character materialCharacter(bool two) {
  Character c = impostorCharacter();
  c.materials.resize(two ? 2 : 1);
  for (size_t m = 0; m < c.materials.size(); ++m) {
    c.materials[m].name = "m" + std::to_string(m);
    c.materials[m].metallic_factor = kMetallic[m];
    c.materials[m].roughness_factor = kRoughness[m];
  }
  for (SubMesh& s : c.mesh.sub_meshes) s.material = 0;
  if (two) c.mesh.sub_meshes[0].material = 1;
  return c;
}

// A value as the atlas's 8 bits hold it.
float stored(float v) {
  return std::round(v * 255.0f) / 255.0f;
}

TEST_P(RenderTest, AnImpostorOfOneSurfaceValueHandsTheMaterialThatValue) {
  for (const bool two : {false, true}) {
    SCOPED_TRACE(two ? "two materials" : "one material");
    Renderer r;
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    ASSERT_TRUE(r.init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(r.addCharacter(materialCharacter(two), palette(), &id).isOk());
    MaterialDesc md;
    md.name = "probe";
    md.source = kPbrProbe;
    MaterialId mid;
    ASSERT_TRUE(r.addMaterial(md, &mid).isOk());
    ASSERT_TRUE(r.setMaterial(id, mid).isOk());
    ImpostorInfo built;
    const Status s = r.buildImpostor(id, smallImpostor(), &built);
    ASSERT_TRUE(s.isOk()) << s.toString();
    EXPECT_EQ(built.uniform_surface, !two);

    CrowdManager crowd;
    initEveryOneAt(true, &crowd);
    if (HasFatalFailure()) return;
    for (int k = 0; k < 6; ++k)
      addHeld(&crowd, {(k - 2.5) * 1.1, -0.9, -4.0 - 3.0 * (k % 3)}, 0.8f * float(k), uint32_t(k),
              0.2 * k);
    if (HasFatalFailure()) return;
    ASSERT_TRUE(crowd.update(0.0, flatCamera()).isOk());
    for (const PathKind kind : {PathKind::kInstanced, PathKind::kGpuDriven}) {
      SCOPED_TRACE(pathKindName(kind));
      TwoTargets targets(kSize, GL_RGBA32F);
      targets.clear(glm::vec4(0.0f));
      DrawStats stats;
      ASSERT_TRUE(drawOnPath(r, kind, crowd, flatCamera(), &stats).isOk());
      const std::vector<glm::vec4> pbr = targets.readFloat(0), index = targets.readFloat(1);
      size_t pixels[2] = {0, 0}, exact = 0, impostor = 0;
      glm::dvec2 sums[2] = {glm::dvec2(0.0), glm::dvec2(0.0)};
      for (size_t p = 0; p < pbr.size(); ++p) {
        if (index[p].a == 0.0f) continue;
        const int m = index[p].x == 1.0f ? 1 : 0;
        ++pixels[m];
        impostor += index[p].y == 1.0f ? 1 : 0;
        sums[m] += glm::dvec2(pbr[p].x, pbr[p].y);
        exact += std::fabs(pbr[p].x - stored(kMetallic[m])) < 1e-6f &&
                         std::fabs(pbr[p].y - stored(kRoughness[m])) < 1e-6f && pbr[p].z == 1.0f
                     ? 1
                     : 0;
      }
      std::printf("[ surface  ] %s, %s: %zu and %zu pixels of materials 0 and 1, %zu exact\n",
                  two ? "two materials" : "one material", pathKindName(kind), pixels[0], pixels[1],
                  exact);
      ASSERT_GT(pixels[0] + pixels[1], 500u);
      EXPECT_EQ(impostor, pixels[0] + pixels[1]) << "every pixel is an impostor's";
      if (!two) {
        EXPECT_EQ(pixels[1], 0u);
        EXPECT_EQ(exact, pixels[0]) << "every pixel holds the material's value as stored";
        continue;
      }
      // Read from the layer: each material's pixels near its values (filtered at their edges).
      ASSERT_GT(pixels[0], 50u) << "the other sub-meshes' material drawn";
      ASSERT_GT(pixels[1], 50u) << "sub-mesh 0's material drawn";
      for (int m = 0; m < 2; ++m) {
        EXPECT_NEAR(sums[m].x / double(pixels[m]), kMetallic[m], 0.05) << "material " << m;
        EXPECT_NEAR(sums[m].y / double(pixels[m]), kRoughness[m], 0.05) << "material " << m;
      }
    }
  }
}

}  // namespace
}  // namespace si
