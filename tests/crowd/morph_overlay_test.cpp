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
#include "si/crowd/blend_space.h"
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

// An empty crowd of the face palette.
void faceCrowd(CrowdManager* crowd) {
  const Face& f = face();
  CrowdDesc cd;
  cd.palette = &f.palette;
  cd.sub_mesh_count = uint32_t(f.character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(f.character.mesh.maxLodCount());
  ASSERT_TRUE(crowd->init(cd).isOk());
}

TEST(MorphOverlay, TheOverlayMovesOnlyTheTargetsOfItsMaskAsItFades) {
  const Face& f = face();
  CrowdManager crowd;
  faceCrowd(&crowd);
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

// A 2D blend's four clips move the targets of its mask by their shares of the blend: the
// weights emulated through the instance's layer record and extra layer records (the chain the
// compose pass walks) equal each clip's weights at its frames summed by si::blendPoint's shares,
// so the third and fourth clips count; off the mask the base clip's stay.
TEST(MorphOverlay, ABlendsFourClipsMoveTheTargetsByTheirShares) {
  const Face& f = face();
  CrowdManager crowd;
  faceCrowd(&crowd);
  LayerMask mask;
  ASSERT_TRUE(
      buildMorphTargetMask(f.character.mesh, f.palette, "face", {"t0", "t1"}, &mask).isOk());
  uint32_t mask_id = 0, space_id = 0;
  ASSERT_TRUE(crowd.addLayerMask(mask, &mask_id).isOk());
  BlendSpace grid;
  grid.name = "grid";
  // The third and fourth clips (wave) animate the targets unlike the first two.
  grid.clips = {f.walk, uint32_t(f.palette.findClip("run")), f.wave, f.wave};
  grid.positions = {0.0f, 1.0f};
  grid.positions_y = {0.0f, 1.0f};
  grid.mask = mask_id;
  ASSERT_TRUE(crowd.addBlendSpace(grid, &space_id).isOk());
  InstanceDesc d;
  d.clip = f.walk;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const Camera camera = test::testCamera({0.0, 1.0, -5.0}, {0.0, 1.0, 0.0});
  for (const glm::vec2 point : {glm::vec2(0.3f, 0.6f), glm::vec2(0.8f, 0.35f)}) {
    SCOPED_TRACE(testing::Message() << point.x << ", " << point.y);
    ASSERT_TRUE(crowd.playBlend(h, space_id, point, 0.0, 0.25).isOk());
    ASSERT_TRUE(crowd.update(0.1, camera).isOk());
    const CrowdView& view = crowd.view();
    ASSERT_EQ(view.records().size(), 1u);
    ASSERT_EQ(view.layerRecords().size(), 1u);
    ASSERT_EQ(view.extraLayerRecords().size(), size_t(kExtraLayerRecords));
    const LayerRecord& layer = view.layerRecords()[0];
    ASSERT_TRUE(layerHasExtras(layer));
    std::vector<float> w(3), base(3), with_two(3);
    ASSERT_TRUE(emulateLayeredMorphWeights(f.palette, view.records()[0], layer,
                                           view.extraLayerRecords(), crowd.layerMasks(), w)
                    .isOk());
    ASSERT_TRUE(emulateRecordMorphWeights(f.palette, view.records()[0], base).isOk());
    ASSERT_TRUE(emulateLayeredMorphWeights(f.palette, view.records()[0], layer, crowd.layerMasks(),
                                           with_two)
                    .isOk());
    // Each clip's weights at its frames: the base record's clip, then each layer's.
    const BlendPoint bp = blendPoint(grid, point.x, point.y);
    ASSERT_EQ(bp.count, 4u);
    const LayerRecord layers[3] = {layer, view.extraLayerRecords()[0], view.extraLayerRecords()[1]};
    std::vector<double> expected(3, 0.0);
    for (uint32_t k = 0; k < 4; ++k) {
      std::vector<float> clip_w(3);
      if (k == 0) {
        clip_w = base;
      } else {
        IntervalMode mode;
        const float fraction = unpackFraction(layers[k - 1].fraction, &mode);
        ASSERT_TRUE(emulateMorphWeights(f.palette, layers[k - 1].frames[0], layers[k - 1].frames[1],
                                        fraction, mode, clip_w)
                        .isOk());
      }
      for (int t = 0; t < 2; ++t) expected[size_t(t)] += double(bp.shares[k]) * clip_w[size_t(t)];
    }
    // The chain's weights are unorm16: 1.5e-5 each.
    for (int t = 0; t < 2; ++t) EXPECT_NEAR(w[size_t(t)], expected[size_t(t)], 1e-4) << t;
    EXPECT_NEAR(w[2], base[2], 1e-6) << "outside the mask: the base clip's";
    // The third and fourth clips count: without them the weights are visibly others.
    EXPECT_GT(std::fabs(w[0] - with_two[0]), 0.05);
  }
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
