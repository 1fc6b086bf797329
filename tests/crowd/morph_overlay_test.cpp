// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Overlays on morph targets (issue "Any animated glTF becomes a crowd"): a mask of targets
// (si::buildMorphTargetMask) lets an instance's overlay move those targets by its clip's
// weights, mixed with the base clip's by the overlay's weight as it fades; the record and
// layer record the crowd writes give, emulated as the shader computes them, the reference's
// weights so mixed. Masks of targets are built and checked by name, and the mask table holds
// their bits where the shader reads them.
#include <gtest/gtest.h>

#include <cstring>

#include "crowd/crowd_test_helpers.h"
#include "crowd/morph_face_fixture.h"
#include "si/core/reference_evaluator.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/record_emulation.h"

namespace si {
namespace {

using test::Face;
using test::face;

// The reference's weights of `clip` at clip-local time `t`.
std::vector<double> reference(uint32_t clip, double t) {
  const Face& f = face();
  std::vector<double> w(3);
  const int32_t source = f.character.findClip(f.palette.clips[clip].name);
  EXPECT_GE(source, 0);
  EXPECT_TRUE(
      evaluateMorphWeights(f.character.mesh, f.character.clips[size_t(source)], t, w).isOk());
  return w;
}

// The drawn instance's weights as the shader computes them from its records.
std::vector<float> drawn(const CrowdManager& crowd) {
  std::vector<float> w(3);
  EXPECT_EQ(crowd.view().records().size(), 1u);
  EXPECT_EQ(crowd.view().layerRecords().size(), 1u);
  EXPECT_TRUE(emulateLayeredMorphWeights(face().palette, crowd.view().records()[0],
                                         crowd.view().layerRecords()[0], crowd.layerMasks(), w)
                  .isOk());
  return w;
}

TEST(MorphOverlay, TheOverlayMovesOnlyTheTargetsOfItsMaskAsItFades) {
  const Face& f = face();
  CrowdDesc cd;
  cd.palette = &f.palette;
  cd.sub_mesh_count = uint32_t(f.character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(f.character.mesh.maxLodCount());
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  LayerMask mask;
  ASSERT_TRUE(
      buildMorphTargetMask(f.character.mesh, f.palette, "face", {"t2", "t0"}, &mask).isOk());
  EXPECT_EQ(mask.morph_targets, (std::vector<uint32_t>{0, 2}));
  uint32_t id = 0;
  ASSERT_TRUE(crowd.addLayerMask(mask, &id).isOk());
  InstanceDesc d;
  d.clip = f.walk;
  d.time_seconds = 0.3;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.playOverlay(h, f.wave, id, 0.6f, 0.0, 0.2).isOk());
  const Camera camera = test::testCamera({0.0, 1.0, -5.0}, {0.0, 1.0, 0.0});
  ASSERT_TRUE(crowd.update(0.0, camera).isOk());
  // The palette's frames hold the linear tracks exactly; between them the interpolation is of
  // a straight line: what differs is float rounding and the weight's unorm16.
  const double tolerance = 2e-5;
  const auto expectMix = [&](double walk_t, double wave_t, double weight) {
    const std::vector<double> base = reference(f.walk, walk_t), over = reference(f.wave, wave_t);
    const std::vector<float> w = drawn(crowd);
    EXPECT_NEAR(w[0], (1.0 - weight) * base[0] + weight * over[0], tolerance);
    EXPECT_NEAR(w[1], base[1], tolerance) << "outside the mask: the base clip's";
    EXPECT_NEAR(w[2], (1.0 - weight) * base[2] + weight * over[2], tolerance);
  };
  expectMix(0.3, 0.2, 0.6);
  // Fading out over 1 s: half-way, weight 0.3, both clips 0.5 s on.
  ASSERT_TRUE(crowd.stopOverlay(h, 1.0).isOk());
  ASSERT_TRUE(crowd.update(0.5, camera).isOk());
  expectMix(0.8, 0.7, 0.3);
  // The overlay moves the targets: its weights differ from the base's there.
  EXPECT_GT(std::fabs(reference(f.wave, 0.7)[0] - reference(f.walk, 0.8)[0]), 0.1);
  // A mask of joints alone moves no target.
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(f.character.skeleton, f.palette, "arm", {"r_clavicle"}, &arm).isOk());
  uint32_t arm_id = 0;
  ASSERT_TRUE(crowd.addLayerMask(arm, &arm_id).isOk());
  ASSERT_TRUE(crowd.playOverlay(h, f.wave, arm_id, 1.0f, 0.0).isOk());
  ASSERT_TRUE(crowd.update(0.1, camera).isOk());
  const std::vector<double> base = reference(f.walk, 0.9);
  const std::vector<float> w = drawn(crowd);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(w[k], base[k], tolerance) << k;
}

TEST(MorphOverlay, MasksOfTargetsAreBuiltAndCheckedByName) {
  const Face& f = face();
  LayerMask m;
  Status s = buildMorphTargetMask(f.character.mesh, f.palette, "face", {"t1", "smile"}, &m);
  EXPECT_EQ(s.code(), StatusCode::kNotFound);
  EXPECT_NE(s.message().find("'smile'"), std::string::npos) << s.toString();
  EXPECT_EQ(buildMorphTargetMask(f.character.mesh, f.palette, "face", {}, &m).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(buildMorphTargetMask(f.character.mesh, f.palette, "face", {"t1"}, nullptr).code(),
            StatusCode::kInvalidArgument);
  s = buildMorphTargetMask(f.character.mesh, test::defaultPalette(), "face", {"t1"}, &m);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("bake it with them"), std::string::npos) << s.toString();
  EXPECT_TRUE(m.morph_targets.empty()) << "nothing written on failure";
  ASSERT_TRUE(buildMorphTargetMask(f.character.mesh, f.palette, "face", {"t1"}, &m).isOk());
  EXPECT_TRUE(m.movesTarget(1));
  EXPECT_FALSE(m.movesTarget(0));
  // validate: targets below the palette's count and increasing; a mask holds something.
  LayerMask bad = m;
  bad.morph_targets = {3};
  EXPECT_EQ(bad.validate(f.palette).code(), StatusCode::kInvalidArgument);
  bad.morph_targets = {2, 1};
  EXPECT_EQ(bad.validate(f.palette).code(), StatusCode::kInvalidArgument);
  bad.morph_targets.clear();
  s = bad.validate(f.palette);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("no morph target"), std::string::npos) << s.toString();
  // The table: the slot count, one morph word per mask, each mask's bits after its slots.
  LayerMask arm, both;
  ASSERT_TRUE(buildLayerMask(f.character.skeleton, f.palette, "arm", {"r_clavicle"}, &arm).isOk());
  ASSERT_TRUE(
      buildMorphTargetMask(f.character.mesh, f.palette, "both", {"t0", "t2"}, &both).isOk());
  const LayerMask masks[] = {arm, both};
  const std::vector<int32_t> table = layerMaskTable(Span<const LayerMask>(masks, 2));
  const size_t slots = arm.slot_anchor.size();
  ASSERT_EQ(table.size(), 2 + 2 * (5 * slots + 1));
  EXPECT_EQ(table[0], int32_t(slots));
  EXPECT_EQ(table[1], 1);
  EXPECT_EQ(table[2 + 5 * slots], 0) << "the arm moves no target";
  EXPECT_EQ(table[2 + (5 * slots + 1) + 5 * slots], 0b101);
  EXPECT_EQ(table[2 + (5 * slots + 1)], LayerMask::kNotInMask) << "no joint in the face mask";
}

}  // namespace
}  // namespace si
