// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Layered animation, the CPU half: joint masks of whole branches with their anchors, the
// shader's composition S_base(a) * inverse(S_overlay(a)) * S_overlay(j) equal to layering the
// local transforms, and the measured error of the palette blend against the local-space
// reference (the embedded character waving its right arm while it walks).
#include <gtest/gtest.h>

#include <cstdio>

#include "si/bake/animation_baker.h"
#include "si/bake/layer_error.h"
#include "si/core/default_character.h"
#include "si/core/layer_mask.h"

#include <glm/gtc/matrix_transform.hpp>

namespace si {
namespace {

struct Baked {
  Character character;
  BakedPalette palette;
  BakeReport report;
};

const Baked& baked() {
  static const Baked b = [] {
    Baked out;
    if (!makeDefaultCharacter({}, &out.character).isOk()) std::abort();
    BakeDesc d;
    d.rate_mode = RateMode::kFixed;  // 30 Hz.
    if (!bakePalette(out.character, d, &out.palette, &out.report).isOk()) std::abort();
    return out;
  }();
  return b;
}

int32_t slotOf(const char* joint) {
  const Baked& b = baked();
  return b.palette.skeleton_to_palette[size_t(b.character.skeleton.findJoint(joint))];
}

TEST(LayerMask, ABranchHangsFromItsRootsParent) {
  const Baked& b = baked();
  LayerMask arm;
  const Status s = buildLayerMask(b.character.skeleton, b.palette, "right arm", {"r_clavicle"}, &arm);
  ASSERT_TRUE(s.isOk()) << s.toString();
  EXPECT_TRUE(arm.validate(b.palette).isOk());
  const Skeleton& sk = b.character.skeleton;
  std::vector<uint32_t> expected;
  for (const char* j : {"r_clavicle", "r_upperarm", "r_forearm", "r_hand", "r_weapon"})
    expected.push_back(uint32_t(sk.findJoint(j)));
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(arm.joints, expected);
  for (size_t slot = 0; slot < arm.slot_anchor.size(); ++slot) {
    const uint32_t joint = b.palette.palette_joints[slot];
    const bool in = std::count(expected.begin(), expected.end(), joint) > 0;
    EXPECT_EQ(arm.slot_anchor[slot], in ? slotOf("chest") : LayerMask::kNotInMask) << joint;
  }
  // Two branches: each has its own anchor.
  LayerMask limbs;
  ASSERT_TRUE(buildLayerMask(sk, b.palette, "limbs", {"l_forearm", "r_shin"}, &limbs).isOk());
  EXPECT_EQ(limbs.slot_anchor[size_t(slotOf("l_hand"))], slotOf("l_upperarm"));
  EXPECT_EQ(limbs.slot_anchor[size_t(slotOf("r_foot"))], slotOf("r_thigh"));
  EXPECT_EQ(limbs.slot_anchor[size_t(slotOf("l_upperarm"))], LayerMask::kNotInMask);
  // An explicit list naming the same joints builds the same mask.
  LayerMask listed;
  ASSERT_TRUE(buildLayerMaskFromJoints(sk, b.palette, "right arm",
                                       {"r_weapon", "r_hand", "r_forearm", "r_upperarm", "r_clavicle"},
                                       &listed).isOk());
  EXPECT_EQ(listed.slot_anchor, arm.slot_anchor);
  EXPECT_EQ(listed.joints, arm.joints);
}

TEST(LayerMask, RefusesWhatIsNotAWholeBranchOrNotInThePalette) {
  const Baked& b = baked();
  const Skeleton& sk = b.character.skeleton;
  LayerMask m;
  m.name = "untouched";
  EXPECT_EQ(buildLayerMask(sk, b.palette, "x", {"tail"}, &m).code(), StatusCode::kNotFound);
  EXPECT_EQ(buildLayerMask(sk, b.palette, "x", {}, &m).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(buildLayerMask(sk, b.palette, "x", {"head"}, nullptr).code(), StatusCode::kInvalidArgument);
  const Status partial = buildLayerMaskFromJoints(sk, b.palette, "x", {"r_forearm"}, &m);
  EXPECT_EQ(partial.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(partial.message().find("r_hand"), std::string::npos) << partial.message();
  EXPECT_EQ(m.name, "untouched");  // Nothing written on failure.
  // Another skeleton than the palette's.
  Skeleton small = sk;
  small.parents.pop_back();
  small.joint_names.pop_back();
  small.rest_pose.pop_back();
  small.inverse_bind_matrices.pop_back();
  EXPECT_EQ(buildLayerMask(small, b.palette, "x", {"head"}, &m).code(), StatusCode::kInvalidArgument);
  // An anchor the palette does not store: the palette's slot of "chest" taken away.
  BakedPalette no_chest = b.palette;
  const size_t chest = size_t(sk.findJoint("chest"));
  no_chest.skeleton_to_palette[chest] = -1;
  const Status unstored = buildLayerMask(sk, no_chest, "x", {"neck"}, &m);
  EXPECT_EQ(unstored.code(), StatusCode::kNotFound);
  EXPECT_NE(unstored.message().find("chest"), std::string::npos) << unstored.message();
  // validate() catches an anchor inside the mask and a wrong size.
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(sk, b.palette, "arm", {"r_clavicle"}, &arm).isOk());
  LayerMask bad = arm;
  bad.slot_anchor[size_t(slotOf("r_hand"))] = slotOf("r_forearm");
  EXPECT_EQ(bad.validate(b.palette).code(), StatusCode::kInvalidArgument);
  bad = arm;
  bad.slot_anchor.pop_back();
  EXPECT_EQ(bad.validate(b.palette).code(), StatusCode::kInvalidArgument);
}

// At weight 1 the shader's composition from model-space skinning matrices is the local-space
// layering exactly: compared on the reference's own (unbaked) matrices, only float rounding
// remains; taking the overlay's matrix alone (the naive switch) detaches the arm.
TEST(LayeredAnimation, TheCompositionIsTheLocalSpaceLayering) {
  const Baked& b = baked();
  const Character& c = b.character;
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(c.skeleton, b.palette, "arm", {"r_clavicle"}, &arm).isOk());
  const Clip& walk = c.clips[size_t(c.findClip("walk"))];
  const Clip& wave = c.clips[size_t(c.findClip("wave"))];
  double worst_composed = 0.0, worst_naive = 0.0;
  for (double t : {0.1, 0.37, 0.8, 1.3}) {
    ReferencePose base, overlay, layered;
    ASSERT_TRUE(evaluatePose(c.skeleton, walk, t, &base).isOk());
    ASSERT_TRUE(evaluatePose(c.skeleton, wave, t, &overlay).isOk());
    ASSERT_TRUE(evaluateLayeredPose(c.skeleton, walk, t, wave, t, arm, 1.0, &layered).isOk());
    for (size_t slot = 0; slot < arm.slot_anchor.size(); ++slot) {
      const int32_t a = arm.slot_anchor[slot];
      if (a == LayerMask::kNotInMask) continue;
      const uint32_t j = b.palette.palette_joints[slot], ja = b.palette.palette_joints[size_t(a)];
      const glm::mat4 composed =
          emulateLayeredMatrix(glm::mat4(base.skinning[j]), glm::mat4(overlay.skinning[j]),
                               glm::mat4(base.skinning[ja]), glm::mat4(overlay.skinning[ja]), a, 1.0f);
      const glm::dvec3 p = glm::dvec3(glm::inverse(c.skeleton.inverse_bind_matrices[j])[3]);
      const glm::dvec3 expected = glm::dvec3(layered.skinning[j] * glm::dvec4(p, 1.0));
      worst_composed = std::max(worst_composed,
                                glm::length(glm::dvec3(composed * glm::vec4(p, 1.0)) - expected));
      worst_naive = std::max(worst_naive,
                             glm::length(glm::dvec3(overlay.skinning[j] * glm::dvec4(p, 1.0)) - expected));
    }
  }
  std::printf("[ layered  ] composition %.3g units, naive switch %.3g units\n", worst_composed, worst_naive);
  EXPECT_LT(worst_composed, 2e-6);
  EXPECT_GT(worst_naive, 1e-3);  // The walk moves the chest; the naive arm does not follow.
}

// The palette blend against the reference blending local transforms: at weight 1 only the
// palette's sampling remains (bounded by the two clips' own bake errors, propagated through the
// anchor); at weights between, blending each joint's whole rigid motion instead of each local
// transform adds to it (the wave raises the arm 139 degrees and bends the forearm: the hand's
// path between is not the chain's), which the report says. An element-wise lerp measured
// 1.04 units there (the arm shrinks half-way); a blend that turned each joint the shorter way
// regardless of its parents, 2.1 (the hand passes half a turn).
TEST(LayeredAnimation, TheMeasuredErrorIsReportedPerWeight) {
  const Baked& b = baked();
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(b.character.skeleton, b.palette, "arm", {"r_clavicle"}, &arm).isOk());
  const uint32_t walk = uint32_t(b.palette.findClip("walk")), wave = uint32_t(b.palette.findClip("wave"));
  LayeredErrorReport r;
  const Status s = measureLayeredError(b.character, b.palette, arm, walk, wave, {0.0f, 0.5f, 1.0f}, &r, 32);
  ASSERT_TRUE(s.isOk()) << s.toString();
  ASSERT_EQ(r.per_weight.size(), 3u);
  const double bake_error = b.report.clips[walk].max_error_units + b.report.clips[wave].max_error_units;
  for (const auto& at : r.per_weight)
    std::printf("[ layered  ] weight %.2f: %.3g units (%.3g of the height)\n", at.weight,
                at.max_error_units, at.max_error_ratio);
  std::printf("[ layered  ] clips' own bake errors: walk %.3g, wave %.3g units\n",
              b.report.clips[walk].max_error_units, b.report.clips[wave].max_error_units);
  // Weight 0 is the base clip as baked.
  EXPECT_LE(r.per_weight[0].max_error_units, b.report.clips[walk].max_error_units * 1.01 + 1e-6);
  // Weight 1: the sampling of both clips, through the anchor's composition (three matrices).
  EXPECT_LE(r.per_weight[2].max_error_units, 3.0 * bake_error + 1e-5);
  EXPECT_GT(r.per_weight[2].max_error_units, 0.0);
  EXPECT_GT(r.per_weight[1].max_error_units, 10.0 * r.per_weight[2].max_error_units);
  EXPECT_LT(r.per_weight[1].max_error_ratio, 0.12);
  EXPECT_DOUBLE_EQ(r.max_error_units, std::max({r.per_weight[0].max_error_units,
                                                r.per_weight[1].max_error_units,
                                                r.per_weight[2].max_error_units}));
  EXPECT_NEAR(r.max_error_ratio, r.max_error_units / double(b.character.height()), 1e-12);
  // Refused input.
  EXPECT_EQ(measureLayeredError(b.character, b.palette, arm, walk, 99, {}, &r).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(measureLayeredError(b.character, b.palette, arm, walk, wave, {1.5f}, &r).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(measureLayeredError(b.character, b.palette, LayerMask(), walk, wave, {}, &r).code(),
            StatusCode::kInvalidArgument);
}

glm::mat4 turnZ(float degrees, float pivot_x) {
  return glm::translate(glm::mat4(1.0f), {pivot_x, 0, 0}) *
         glm::rotate(glm::mat4(1.0f), glm::radians(degrees), {0, 0, 1}) *
         glm::translate(glm::mat4(1.0f), {-pivot_x, 0, 0});
}

// A two-joint chain on the model anchor: the overlay turns the parent 140 degrees and the child
// 60 more (200 in all). Half-way the reference turns them 70 and 30: the child has turned 100
// degrees. Given its parent's chain, the blend turns the child the chain's way (+100, exactly
// that rotation); without it, the shorter way (-80).
TEST(LayeredAnimation, TheBlendTurnsAJointTheWayItsChainTurns) {
  const glm::mat4 identity(1.0f);
  const glm::mat4 parent = turnZ(140, 0), child = parent * turnZ(60, 1);
  const glm::mat4 chain_base[] = {identity}, chain_overlay[] = {parent};
  const glm::mat4 along = emulateLayeredMatrix(identity, child, identity, identity,
                                               LayerMask::kModelAnchor, 0.5f, chain_base, chain_overlay);
  const glm::mat4 shorter =
      emulateLayeredMatrix(identity, child, identity, identity, LayerMask::kModelAnchor, 0.5f);
  const float along_deg = glm::degrees(std::atan2(along[0][1], along[0][0]));
  const float shorter_deg = glm::degrees(std::atan2(shorter[0][1], shorter[0][0]));
  EXPECT_NEAR(along_deg, 100.0f, 1e-3f);
  EXPECT_NEAR(shorter_deg, -80.0f, 1e-3f);
  // The child's tip against the reference's (70 then 30 about the child's pivot): the screw
  // turns about one pivot where the chain turns about two, 0.46 apart on a chain of length 2.
  const glm::vec4 tip(2, 0, 0, 1);
  const glm::vec3 reference = turnZ(70, 0) * turnZ(30, 1) * tip;
  EXPECT_LT(glm::distance(glm::vec3(along * tip), reference), 0.5f);
  EXPECT_GT(glm::distance(glm::vec3(shorter * tip), reference), 1.5f);
  // The ends are the base and the layered matrix whatever the chain.
  EXPECT_EQ(emulateLayeredMatrix(identity, child, identity, identity, LayerMask::kModelAnchor, 0.0f,
                                 chain_base, chain_overlay),
            identity);
  EXPECT_EQ(emulateLayeredMatrix(identity, child, identity, identity, LayerMask::kModelAnchor, 1.0f,
                                 chain_base, chain_overlay),
            child);
}

TEST(LayeredAnimation, ChainsFollowTheMasksParentSlots) {
  const Baked& b = baked();
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(b.character.skeleton, b.palette, "arm", {"r_clavicle"}, &arm).isOk());
  const std::vector<uint32_t> hand = layerChain(arm, uint32_t(slotOf("r_hand")));
  const std::vector<uint32_t> expected{uint32_t(slotOf("r_forearm")), uint32_t(slotOf("r_upperarm")),
                                       uint32_t(slotOf("r_clavicle"))};
  EXPECT_EQ(hand, expected);
  EXPECT_TRUE(layerChain(arm, uint32_t(slotOf("r_clavicle"))).empty());  // The branch root.
  EXPECT_EQ(arm.slot_parent[size_t(slotOf("head"))], LayerMask::kNoParentSlot);
  // The table holds each mask's anchors, then its parents.
  const std::vector<int32_t> table = layerMaskTable(Span<const LayerMask>(&arm, 1));
  ASSERT_EQ(table.size(), 1 + 2 * arm.slot_anchor.size());
  EXPECT_EQ(table[1 + arm.slot_anchor.size() + size_t(slotOf("r_hand"))], slotOf("r_forearm"));
  // A cycle of parent slots is refused: the shader follows them.
  LayerMask bad = arm;
  bad.slot_parent[size_t(slotOf("r_clavicle"))] = slotOf("r_hand");
  const Status s = bad.validate(b.palette);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("cycle"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace si
