// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Per-part LOD (si::buildPartLods): each part's level at each character level chosen by its
// own errors, parts dropped by their measured distance to the kept parts (over poses), the
// character's error per level unchanged, a second call a no-op, bad input refused untouched.
#include <gtest/gtest.h>

#include "core/test_helpers.h"
#include "si/core/default_character.h"
#include "si/core/part_lod.h"

namespace si {
namespace {

using test::chainSkeleton;

// Appends the square |x|, |y| <= half at height z, skinned to `joint`, as a sub-mesh whose
// levels all draw it with the given errors.
void addSquare(Character* c, const char* name, float half, float z, uint16_t joint,
               std::vector<float> errors) {
  SkinnedMesh& m = c->mesh;
  const uint32_t base = uint32_t(m.positions.size());
  for (glm::vec2 corner : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
    m.positions.push_back(glm::vec3(corner * half, z));
    m.normals.push_back(glm::vec3(0, 0, 1));
    m.joints.push_back(glm::u16vec4(joint, 0, 0, 0));
    m.weights.push_back(glm::vec4(1, 0, 0, 0));
  }
  const uint32_t first = uint32_t(m.indices.size());
  for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
  SubMesh sm;
  sm.name = name;
  sm.lods.assign(errors.size(), IndexRange{first, 6});
  sm.lod_error_units = std::move(errors);
  m.sub_meshes.push_back(sm);
}

// A body (2 x 2 square, the largest part: kept), a badge 0.05 above it on joint 1, and a flag
// 1.0 above it, with chains of 3, 2 and 4 levels.
Character threeParts() {
  Character c;
  c.name = "parts";
  c.skeleton = chainSkeleton(2);
  addSquare(&c, "body", 1.0f, 0.0f, 0, {0.0f, 0.1f, 0.3f});
  addSquare(&c, "badge", 0.1f, 0.05f, 1, {0.0f, 0.02f});
  addSquare(&c, "flag", 0.5f, 1.0f, 0, {0.0f, 0.05f, 0.2f, 0.4f});
  return c;
}

// With drops at 0.05 (badge) and 1.0 (flag), the character's errors are 0, 0.1, 0.3, 0.4 (the
// flag's level 3) and 1.0 (its drop), and each part takes the coarsest level within them.
TEST(PartLod, EachPartTakesItsCoarsestLevelWithinTheCharactersError) {
  Character c = threeParts();
  PartLodReport report;
  ASSERT_TRUE(buildPartLods(&c, {}, &report).isOk());
  ASSERT_EQ(report.parts.size(), 3u);
  EXPECT_TRUE(report.parts[0].kept);
  EXPECT_FALSE(report.parts[1].kept);
  EXPECT_NEAR(report.parts[1].drop_error_units, 0.05f, 1e-6f);
  EXPECT_NEAR(report.parts[2].drop_error_units, 1.0f, 1e-6f);
  EXPECT_LT(report.parts[0].drop_error_units, 0.0f);
  const std::vector<float> expected_errors = {0.0f, 0.1f, 0.3f, 0.4f, 1.0f};
  ASSERT_EQ(report.level_errors_units.size(), expected_errors.size());
  for (size_t l = 0; l < expected_errors.size(); ++l)
    EXPECT_NEAR(report.level_errors_units[l], expected_errors[l], 1e-6f) << l;
  EXPECT_EQ(report.parts[0].level_of, (std::vector<int>{0, 1, 2, 2, 2}));
  EXPECT_EQ(report.parts[1].level_of, (std::vector<int>{0, -1, -1, -1, -1}));
  EXPECT_EQ(report.parts[2].level_of, (std::vector<int>{0, 1, 2, 3, -1}));
  EXPECT_EQ(report.triangles_before, (std::vector<uint64_t>{6, 6, 6, 6, 6}));
  EXPECT_EQ(report.triangles_after, (std::vector<uint64_t>{6, 4, 4, 4, 2}));

  // The mesh draws what the report says; its error per level is the report's.
  ASSERT_EQ(c.mesh.maxLodCount(), 5u);
  ASSERT_TRUE(c.mesh.validate(2).isOk());
  for (size_t sm = 0; sm < 3; ++sm)
    for (size_t l = 0; l < 5; ++l)
      EXPECT_EQ(c.mesh.sub_meshes[sm].lods[l].index_count,
                report.parts[sm].level_of[l] < 0 ? 0u : 6u) << sm << " " << l;
  std::vector<float> errors;
  ASSERT_TRUE(lodErrorsByLevel(c.mesh, &errors).isOk());
  for (size_t l = 0; l < errors.size(); ++l) EXPECT_NEAR(errors[l], expected_errors[l], 1e-6f);

  // A second call finds nothing more to do.
  const SkinnedMesh once = c.mesh;
  ASSERT_TRUE(buildPartLods(&c, {}, &report).isOk());
  for (size_t sm = 0; sm < 3; ++sm) {
    ASSERT_EQ(c.mesh.sub_meshes[sm].lods.size(), once.sub_meshes[sm].lods.size());
    for (size_t l = 0; l < once.sub_meshes[sm].lods.size(); ++l) {
      EXPECT_EQ(c.mesh.sub_meshes[sm].lods[l].index_count, once.sub_meshes[sm].lods[l].index_count);
      EXPECT_EQ(c.mesh.sub_meshes[sm].lod_error_units[l], once.sub_meshes[sm].lod_error_units[l]);
    }
  }
  EXPECT_EQ(report.triangles_after, (std::vector<uint64_t>{6, 4, 4, 4, 2}));
  // Its empty levels keep their errors through a re-measurement of the others.
  ASSERT_TRUE(measureLodErrors(&c.mesh, true).isOk());
  EXPECT_NEAR(c.mesh.sub_meshes[1].lod_error_units[1], 0.05f, 1e-6f);
}

// A part's drop counts as one level past the character's last: a short chain (the badge's 2
// levels) does not put its drop, 0.35 here, at level 2, which would raise the character's
// error there from 0.3.
TEST(PartLod, ADropNeverRaisesAnExistingLevelsError) {
  Character c = threeParts();
  for (size_t v = 4; v < 8; ++v) c.mesh.positions[v].z = 0.35f;  // The badge, 0.35 up.
  std::vector<float> before;
  ASSERT_TRUE(lodErrorsByLevel(c.mesh, &before).isOk());
  PartLodReport report;
  ASSERT_TRUE(buildPartLods(&c, {}, &report).isOk());
  EXPECT_NEAR(report.parts[1].drop_error_units, 0.35f, 1e-6f);
  std::vector<float> after;
  ASSERT_TRUE(lodErrorsByLevel(c.mesh, &after).isOk());
  ASSERT_EQ(before.size(), 4u);
  ASSERT_EQ(after.size(), 5u);  // The flag's drop (1.0) adds a level.
  for (size_t l = 0; l < before.size(); ++l) EXPECT_EQ(after[l], before[l]) << l;
  EXPECT_EQ(report.parts[1].level_of, (std::vector<int>{0, 1, 1, -1, -1}));
}

// Without drops each part still takes its coarsest level within the character's error; a kept
// part is never dropped.
TEST(PartLod, KeepMaskAndDropOffKeepParts) {
  Character c = threeParts();
  PartLodDesc d;
  d.drop = false;
  PartLodReport report;
  ASSERT_TRUE(buildPartLods(&c, d, &report).isOk());
  // Errors 0, 0.1, 0.3, 0.4: the flag's level 1 (0.05) is within 0.1 at level 1 already.
  EXPECT_EQ(report.parts[1].level_of, (std::vector<int>{0, 1, 1, 1}));
  EXPECT_EQ(report.parts[2].level_of, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_LT(report.parts[2].drop_error_units, 0.0f);

  Character k = threeParts();
  d = PartLodDesc();
  d.keep_mask = 0b101;  // Body and flag.
  ASSERT_TRUE(buildPartLods(&k, d, &report).isOk());
  EXPECT_TRUE(report.parts[2].kept);
  EXPECT_EQ(report.parts[2].level_of, (std::vector<int>{0, 1, 2, 3}));
  // The badge is measured against the flag too: still 0.05 from the body.
  EXPECT_NEAR(report.parts[1].drop_error_units, 0.05f, 1e-6f);
  EXPECT_EQ(report.parts[1].level_of, (std::vector<int>{0, -1, -1, -1}));
}

// A drop is measured over the clips' poses: the badge's joint lifts it 0.5 at the clip's end.
TEST(PartLod, DropErrorsAreMeasuredOverThePoses) {
  Character c = threeParts();
  Clip clip = test::emptyClip(2, 1.0f);
  clip.joint_tracks[1].translation.times_seconds = {0.0f, 1.0f};
  clip.joint_tracks[1].translation.values = {glm::vec3(0, 1, 0), glm::vec3(0, 1, 0.5f)};
  c.clips.push_back(clip);
  Character rest_only = c;
  PartLodReport report;
  ASSERT_TRUE(buildPartLods(&c, {}, &report).isOk());
  EXPECT_NEAR(report.parts[1].drop_error_units, 0.55f, 1e-5f);
  // 0.55 is past the errors of levels 1 to 3 (0.1, 0.3, 0.4): kept at its level 1 there, ...
  EXPECT_EQ(report.parts[1].level_of, (std::vector<int>{0, 1, 1, 1, -1}));
  // ... dropped at level 4, which the flag's drop (1.0) adds.
  PartLodDesc d;
  d.poses.max_poses = 1;  // The rest pose only.
  ASSERT_TRUE(buildPartLods(&rest_only, d, &report).isOk());
  EXPECT_NEAR(report.parts[1].drop_error_units, 0.05f, 1e-6f);
}

TEST(PartLod, BadInputIsRefusedAndLeavesTheCharacterUntouched) {
  EXPECT_EQ(buildPartLods(nullptr, {}, nullptr).code(), StatusCode::kInvalidArgument);
  Character c = threeParts();
  c.mesh.sub_meshes[2].lod_error_units.clear();
  Status s = buildPartLods(&c, {}, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("'flag' has no LOD errors"), std::string::npos) << s.message();
  EXPECT_EQ(c.mesh.sub_meshes[0].lods.size(), 3u);

  c = threeParts();
  PartLodDesc d;
  d.keep_mask = 0b1000;  // Past the three sub-meshes.
  s = buildPartLods(&c, d, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("keep_mask"), std::string::npos) << s.message();
  EXPECT_EQ(c.mesh.sub_meshes[1].lods.size(), 2u);

  c = threeParts();
  c.mesh.indices[0] = 99;  // Invalid mesh: validate()'s status.
  EXPECT_EQ(buildPartLods(&c, {}, nullptr).code(), StatusCode::kOutOfRange);

  // An empty level without an error cannot be measured.
  c = threeParts();
  c.mesh.sub_meshes[1].lods.push_back(IndexRange{0, 0});
  c.mesh.sub_meshes[1].lod_error_units.clear();
  ASSERT_TRUE(c.mesh.validate(2).isOk());  // Empty past LOD 0 is valid ...
  s = measureLodErrors(&c.mesh, false);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("is empty"), std::string::npos) << s.message();
  c.mesh.sub_meshes[1].lods[0].index_count = 0;  // ... at LOD 0 it is not.
  EXPECT_EQ(c.mesh.validate(2).code(), StatusCode::kOutOfRange);
}

// The embedded character (3 levels): the parts are measured against the body and the triangles
// never grow; the character's error per level is unchanged.
TEST(PartLod, TheEmbeddedCharacterDrawsFewerTrianglesAtTheSameError) {
  Character c;
  ASSERT_TRUE(makeDefaultCharacter({}, &c).isOk());
  AnimatedLodErrorDesc poses;  // A few poses: the test is about the mapping, not the errors.
  poses.poses_per_clip = 2;
  poses.max_poses = 12;
  ASSERT_TRUE(measureAnimatedLodErrors(&c, poses).isOk());
  std::vector<float> before;
  ASSERT_TRUE(lodErrorsByLevel(c.mesh, &before).isOk());
  PartLodReport report;
  PartLodDesc pd;
  pd.poses = poses;
  ASSERT_TRUE(buildPartLods(&c, pd, &report).isOk());
  EXPECT_TRUE(report.parts[0].kept);  // The body: the largest.
  std::vector<float> after;
  ASSERT_TRUE(lodErrorsByLevel(c.mesh, &after).isOk());
  ASSERT_GE(after.size(), before.size());
  for (size_t l = 0; l < before.size(); ++l) EXPECT_EQ(after[l], before[l]) << l;
  uint64_t saved = 0;
  for (size_t l = 0; l < report.triangles_after.size(); ++l) {
    EXPECT_LE(report.triangles_after[l], report.triangles_before[l]) << l;
    saved += report.triangles_before[l] - report.triangles_after[l];
  }
  EXPECT_GT(saved, 0u);
  for (const PartLodReport::Part& p : report.parts) {
    if (!p.kept) {
      EXPECT_GT(p.drop_error_units, 0.0f) << p.name;
    }
  }
  // The helmet sits on the head; the spear reaches a metre above the hand.
  ASSERT_EQ(report.parts[1].name, "helmet");
  ASSERT_EQ(report.parts[3].name, "spear");
  EXPECT_LT(report.parts[1].drop_error_units, 0.1f);
  EXPECT_GT(report.parts[3].drop_error_units, 0.5f);
}

}  // namespace
}  // namespace si
