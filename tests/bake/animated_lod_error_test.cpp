// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// LOD errors over the clips' poses: never below the bind-pose error, above it where the
// simplifier welded parts that move apart, measured again when asked; bad input refused with
// the character untouched.
#include <gtest/gtest.h>

#include <cmath>

#include "core/test_helpers.h"
#include "si/bake/lod_chain.h"
#include "si/core/default_character.h"
#include "si/core/lod_error.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {

Character embeddedWithChain() {
  Character c = test::embeddedCharacter();
  EXPECT_TRUE(buildLodChain(&c.mesh, {}, nullptr).isOk());
  return c;
}

Span<const uint32_t> lodSpan(const SkinnedMesh& m, const SubMesh& sm, size_t l) {
  return Span<const uint32_t>(m.indices.data() + sm.lods[l].first_index, sm.lods[l].index_count);
}

TEST(AnimatedLodError, RaisesTheBindPoseErrorWhereAPoseMovesWeldedParts) {
  const Character bind = embeddedWithChain();
  Character c = bind;
  std::vector<std::vector<int>> worst;
  ASSERT_TRUE(measureAnimatedLodErrors(&c, {}, &worst).isOk());
  ASSERT_EQ(worst.size(), c.mesh.sub_meshes.size());
  bool raised = false;
  for (size_t sm = 0; sm < c.mesh.sub_meshes.size(); ++sm) {
    const SubMesh& a = c.mesh.sub_meshes[sm];
    const SubMesh& b = bind.mesh.sub_meshes[sm];
    ASSERT_EQ(a.lod_error_units.size(), b.lod_error_units.size());
    ASSERT_EQ(worst[sm].size(), a.lods.size());
    EXPECT_EQ(a.lod_error_units[0], 0.0f);
    for (size_t l = 1; l < a.lods.size(); ++l) {
      EXPECT_GE(a.lod_error_units[l], b.lod_error_units[l]) << a.name << " " << l;
      EXPECT_GE(a.lod_error_units[l], a.lod_error_units[l - 1]) << a.name << " " << l;
      raised |= a.lod_error_units[l] > b.lod_error_units[l] * 1.2f;
      if (worst[sm][l] >= 0) {
        // The pose it names does have that error (within the sampling's float rounding).
        const Clip& clip = c.clips[size_t(worst[sm][l])];
        float best_seen = 0.0f;
        for (uint32_t k = 0; k < 8; ++k) {
          ReferencePose pose;
          ASSERT_TRUE(evaluateLocalPose(c.skeleton, clip, clip.duration_seconds * k / 7.0, &pose)
                          .isOk());
          std::vector<glm::dvec3> skinned(c.mesh.vertexCount());
          ASSERT_TRUE(skinVertices(c.mesh, pose.skinning,
                                   Span<glm::dvec3>(skinned.data(), skinned.size()), {}, {})
                          .isOk());
          std::vector<glm::vec3> p(skinned.begin(), skinned.end());
          float e = 0.0f;
          ASSERT_TRUE(surfaceDistance(p, lodSpan(c.mesh, a, 0), lodSpan(c.mesh, a, l), &e).isOk());
          best_seen = std::max(best_seen, e);
        }
        EXPECT_NEAR(best_seen, a.lod_error_units[l], 1e-5f + 1e-4f * best_seen)
            << a.name << " " << l;
      }
    }
  }
  // The sloppy levels weld the legs of the embedded body; walking pulls them apart.
  EXPECT_TRUE(raised);
  // Measuring again finds nothing higher: errors are stable.
  Character again = c;
  ASSERT_TRUE(measureAnimatedLodErrors(&again, {}, nullptr).isOk());
  for (size_t sm = 0; sm < c.mesh.sub_meshes.size(); ++sm)
    EXPECT_EQ(again.mesh.sub_meshes[sm].lod_error_units, c.mesh.sub_meshes[sm].lod_error_units);
}

TEST(AnimatedLodError, ThePoseCountIsBounded) {
  // max_poses 1 measures the rest pose only: never more than all poses, and less somewhere.
  Character full = embeddedWithChain();
  Character rest_only = full;
  ASSERT_TRUE(measureAnimatedLodErrors(&full, {}, nullptr).isOk());
  AnimatedLodErrorDesc one;
  one.max_poses = 1;
  ASSERT_TRUE(measureAnimatedLodErrors(&rest_only, one, nullptr).isOk());
  bool lower_somewhere = false;
  for (size_t sm = 0; sm < full.mesh.sub_meshes.size(); ++sm)
    for (size_t l = 1; l < full.mesh.sub_meshes[sm].lods.size(); ++l) {
      EXPECT_LE(rest_only.mesh.sub_meshes[sm].lod_error_units[l],
                full.mesh.sub_meshes[sm].lod_error_units[l]);
      lower_somewhere |= rest_only.mesh.sub_meshes[sm].lod_error_units[l] <
                         full.mesh.sub_meshes[sm].lod_error_units[l];
    }
  EXPECT_TRUE(lower_somewhere);
}

TEST(AnimatedLodError, BadInputIsRefusedAndLeavesTheCharacterUntouched) {
  EXPECT_EQ(measureAnimatedLodErrors(nullptr, {}, nullptr).code(), StatusCode::kInvalidArgument);
  Character c = embeddedWithChain();
  const Character before = c;
  c.clips[0].joint_tracks.pop_back();  // A clip that does not match the skeleton.
  const Status s = measureAnimatedLodErrors(&c, {}, nullptr);
  EXPECT_FALSE(s.isOk());
  EXPECT_NE(s.message().find("clip 0"), std::string::npos) << s.toString();
  for (size_t sm = 0; sm < c.mesh.sub_meshes.size(); ++sm)
    EXPECT_EQ(c.mesh.sub_meshes[sm].lod_error_units, before.mesh.sub_meshes[sm].lod_error_units);
  Character bad_mesh = embeddedWithChain();
  bad_mesh.mesh.indices[0] = 1u << 30;  // Past the vertices.
  EXPECT_FALSE(measureAnimatedLodErrors(&bad_mesh, {}, nullptr).isOk());
}

}  // namespace
}  // namespace si
