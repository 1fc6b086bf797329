// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Layered animation, the CPU half: joint masks of whole branches with their anchors, the
// shader's composition S_base(a) * inverse(S_overlay(a)) * S_overlay(j) equal to layering the
// local transforms, and the measured error of the palette blend against the local-space
// reference (the embedded character waving its right arm while it walks).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <limits>

#include "si/bake/animation_baker.h"
#include "si/bake/layer_error.h"
#include "si/core/default_character.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_manager.h"

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
  // ... and bind origins: one per slot, finite where masked.
  bad = arm;
  bad.slot_bind_origin.pop_back();
  EXPECT_EQ(bad.validate(b.palette).code(), StatusCode::kInvalidArgument);
  bad = arm;
  bad.slot_bind_origin[size_t(slotOf("r_hand"))].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(bad.validate(b.palette).code(), StatusCode::kNotFinite);
  bad.slot_bind_origin[size_t(slotOf("r_hand"))].y = 0.0f;
  bad.slot_bind_origin[size_t(slotOf("head"))].y = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(bad.validate(b.palette).isOk());  // Outside the mask: never read.
  // Each masked slot's bind origin is its joint's, from the inverse bind matrix.
  const size_t hand = size_t(sk.findJoint("r_hand"));
  const glm::vec3 origin(glm::inverse(sk.inverse_bind_matrices[hand])[3]);
  EXPECT_LT(glm::distance(arm.slot_bind_origin[size_t(slotOf("r_hand"))], origin), 1e-6f);
  EXPECT_GT(glm::length(origin), 0.1f);
}

// The shader's blend from model-space skinning matrices is the local-space layering: at
// weight 1 the composition S_base(a) * inverse(S_overlay(a)) * S_overlay(j), between weights
// each link of the chain blended by si::localBlend. Compared on the reference's own (unbaked)
// matrices, only float rounding remains (every joint of the arm mask drives vertices); taking
// the overlay's matrix alone (the naive switch) detaches the arm.
TEST(LayeredAnimation, TheBlendIsTheLocalSpaceLayering) {
  const Baked& b = baked();
  const Character& c = b.character;
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(c.skeleton, b.palette, "arm", {"r_clavicle"}, &arm).isOk());
  const Clip& walk = c.clips[size_t(c.findClip("walk"))];
  const Clip& wave = c.clips[size_t(c.findClip("wave"))];
  double worst_naive = 0.0;
  for (double weight : {0.25, 0.5, 0.9, 1.0}) {
    double worst = 0.0;
    for (double t : {0.1, 0.37, 0.8, 1.3}) {
      ReferencePose base, overlay, layered;
      ASSERT_TRUE(evaluatePose(c.skeleton, walk, t, &base).isOk());
      ASSERT_TRUE(evaluatePose(c.skeleton, wave, t, &overlay).isOk());
      ASSERT_TRUE(evaluateLayeredPose(c.skeleton, walk, t, wave, t, arm, weight, &layered).isOk());
      const auto matrices = [&](const ReferencePose& pose) {
        return [&](uint32_t slot) { return glm::mat4(pose.skinning[b.palette.palette_joints[slot]]); };
      };
      for (uint32_t slot = 0; slot < arm.slot_anchor.size(); ++slot) {
        if (!arm.contains(slot)) continue;
        const uint32_t j = b.palette.palette_joints[slot];
        const glm::mat4 blended = emulateLayeredMatrix(arm, slot, float(weight), matrices(base), matrices(overlay));
        const glm::dvec3 p = glm::dvec3(glm::inverse(c.skeleton.inverse_bind_matrices[j])[3]);
        const glm::dvec3 expected = glm::dvec3(layered.skinning[j] * glm::dvec4(p, 1.0));
        worst = std::max(worst, glm::length(glm::dvec3(blended * glm::vec4(p, 1.0)) - expected));
        if (weight == 1.0)
          worst_naive = std::max(worst_naive,
                                 glm::length(glm::dvec3(overlay.skinning[j] * glm::dvec4(p, 1.0)) - expected));
      }
    }
    std::printf("[ layered  ] weight %.2f: blend %.3g units\n", weight, worst);
    EXPECT_LT(worst, 1e-5) << weight;
  }
  std::printf("[ layered  ] naive switch %.3g units\n", worst_naive);
  EXPECT_GT(worst_naive, 1e-3);  // The walk moves the chest; the naive arm does not follow.
}

// Layers composed one after another (a 2D blend's chain) on a branch hung from the chest:
// emulateLayeredChain from the exact poses' matrices against evaluateLayeredChainPose, at
// several weight sets; weight-0 layers change nothing; a layer at weight 1 replaces those before
// it; one layer is emulateLayeredMatrix.
TEST(LayeredAnimation, AChainOfLayersIsTheLocalSpaceChain) {
  const Baked& b = baked();
  const Character& c = b.character;
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(c.skeleton, b.palette, "arm", {"r_clavicle"}, &arm).isOk());
  const Clip* clips[4] = {&c.clips[size_t(c.findClip("walk"))], &c.clips[size_t(c.findClip("run"))],
                          &c.clips[size_t(c.findClip("wave"))],
                          &c.clips[size_t(c.findClip("idle"))]};
  const double t = 0.37;
  ReferencePose poses[4];
  for (int k = 0; k < 4; ++k) ASSERT_TRUE(evaluatePose(c.skeleton, *clips[k], t, &poses[k]).isOk());
  const auto matrices = [&](const ReferencePose& pose) -> SlotMatrices {
    return [&](uint32_t slot) { return glm::mat4(pose.skinning[b.palette.palette_joints[slot]]); };
  };
  const auto chainError = [&](std::array<float, 3> w) {
    std::vector<LayerPose> layers;
    std::vector<LayerSample> samples;
    for (int k = 0; k < 3; ++k) {
      layers.push_back({matrices(poses[k + 1]), w[k]});
      samples.push_back({clips[k + 1], t, double(w[k])});
    }
    ReferencePose chained;
    EXPECT_TRUE(evaluateLayeredChainPose(c.skeleton, *clips[0], t, samples, arm, &chained).isOk());
    double worst = 0.0;
    for (uint32_t slot = 0; slot < arm.slot_anchor.size(); ++slot) {
      const uint32_t j = b.palette.palette_joints[slot];
      const glm::mat4 m = emulateLayeredChain(arm, slot, matrices(poses[0]), layers);
      const glm::dvec3 p = glm::dvec3(glm::inverse(c.skeleton.inverse_bind_matrices[j])[3]);
      const glm::dvec3 expected = glm::dvec3(chained.skinning[j] * glm::dvec4(p, 1.0));
      worst = std::max(worst, glm::length(glm::dvec3(m * glm::vec4(p, 1.0)) - expected));
    }
    return worst;
  };
  for (const std::array<float, 3>& w :
       {std::array<float, 3>{0.4f, 0.3f, 0.2f}, std::array<float, 3>{0.5f, 0.0f, 0.6f},
        std::array<float, 3>{0.3f, 1.0f, 0.25f}, std::array<float, 3>{0.0f, 0.0f, 1.0f}}) {
    const double e = chainError(w);
    std::printf("[ layered  ] chain %.2f %.2f %.2f: %.3g units\n", w[0], w[1], w[2], e);
    EXPECT_LT(e, 1e-5);
  }
  // The chain's arithmetic: zero weights skipped, weight 1 replacing, one layer as before.
  const uint32_t hand = uint32_t(slotOf("r_hand"));
  const std::vector<LayerPose> one{{matrices(poses[2]), 0.6f}};
  const std::vector<LayerPose> padded{
      {matrices(poses[1]), 0.0f}, {matrices(poses[2]), 0.6f}, {matrices(poses[3]), 0.0f}};
  const std::vector<LayerPose> replaced{{matrices(poses[1]), 0.7f}, {matrices(poses[2]), 1.0f}};
  const std::vector<LayerPose> alone{{matrices(poses[2]), 1.0f}};
  const glm::mat4 single =
      emulateLayeredMatrix(arm, hand, 0.6f, matrices(poses[0]), matrices(poses[2]));
  EXPECT_EQ(emulateLayeredChain(arm, hand, matrices(poses[0]), one), single);
  EXPECT_EQ(emulateLayeredChain(arm, hand, matrices(poses[0]), padded), single);
  EXPECT_EQ(emulateLayeredChain(arm, hand, matrices(poses[0]), replaced),
            emulateLayeredChain(arm, hand, matrices(poses[0]), alone));
  EXPECT_NE(emulateLayeredChain(arm, hand, matrices(poses[0]), replaced), single);
  ReferencePose unused;
  const std::vector<LayerSample> null_clip{{nullptr, 0.0, 0.5}};
  EXPECT_EQ(evaluateLayeredChainPose(c.skeleton, *clips[0], t, null_clip, arm, &unused).code(),
            StatusCode::kInvalidArgument);
  const std::vector<LayerSample> heavy{{clips[1], 0.0, 1.5}};
  EXPECT_EQ(evaluateLayeredChainPose(c.skeleton, *clips[0], t, heavy, arm, &unused).code(),
            StatusCode::kInvalidArgument);
}

// The palette blend against the reference blending local transforms: at every weight only
// the palette's sampling remains, bounded by the two clips' own bake errors propagated through
// the chain's links. Blending each joint's whole rigid motion instead (the dual quaternion
// blend this replaced) measured 0.188 units at weight 0.5 (the wave raises the arm 139 degrees
// and bends the forearm: the hand's path between is not the chain's); an element-wise lerp,
// 1.04 units (the arm shrinks half-way).
TEST(LayeredAnimation, TheMeasuredErrorIsReportedPerWeight) {
  const Baked& b = baked();
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(b.character.skeleton, b.palette, "arm", {"r_clavicle"}, &arm).isOk());
  const uint32_t walk = uint32_t(b.palette.findClip("walk")), wave = uint32_t(b.palette.findClip("wave"));
  LayeredErrorReport r;
  const std::vector<float> weights{0.0f, 0.25f, 0.5f, 0.75f, 1.0f};
  const Status s = measureLayeredError(b.character, b.palette, arm, walk, wave, weights, &r, 32);
  ASSERT_TRUE(s.isOk()) << s.toString();
  ASSERT_EQ(r.per_weight.size(), weights.size());
  const double bake_error = b.report.clips[walk].max_error_units + b.report.clips[wave].max_error_units;
  double worst = 0.0;
  for (const auto& at : r.per_weight) {
    std::printf("[ layered  ] weight %.2f: %.3g units (%.3g of the height)\n", at.weight,
                at.max_error_units, at.max_error_ratio);
    worst = std::max(worst, at.max_error_units);
  }
  std::printf("[ layered  ] clips' own bake errors: walk %.3g, wave %.3g units\n",
              b.report.clips[walk].max_error_units, b.report.clips[wave].max_error_units);
  // Weight 0 is the base clip as baked.
  EXPECT_LE(r.per_weight[0].max_error_units, b.report.clips[walk].max_error_units * 1.01 + 1e-6);
  // Every other weight: the sampling of both clips, through the anchor's composition (three
  // matrices) or the chain's links.
  for (size_t i = 1; i < r.per_weight.size(); ++i) {
    EXPECT_LE(r.per_weight[i].max_error_units, 3.0 * bake_error + 1e-5) << weights[i];
    EXPECT_GT(r.per_weight[i].max_error_units, 0.0) << weights[i];
  }
  EXPECT_DOUBLE_EQ(r.max_error_units, worst);
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

// A two-joint chain on the model anchor (bind origins 0 and 1 on x): the overlay turns the
// parent 140 degrees and the child 60 more (200 in all). Half-way the reference turns them 70
// and 30 about their own origins: the child has turned 100 degrees. The blend follows the
// chain link by link, so it equals that; blending the child's whole motion at once (the dual
// quaternion blend this replaced) turned it about one pivot, 0.46 from the reference at the
// tip, and the shorter way -80 degrees without the chain.
TEST(LayeredAnimation, TheBlendFollowsTheChainLinkByLink) {
  LayerMask chain;
  chain.name = "chain";
  chain.slot_anchor = {LayerMask::kModelAnchor, LayerMask::kModelAnchor};
  chain.slot_parent = {LayerMask::kNoParentSlot, 0};
  chain.slot_bind_origin = {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f)};
  chain.joints = {0, 1};
  const glm::mat4 overlay[] = {turnZ(140, 0), turnZ(140, 0) * turnZ(60, 1)};
  const auto base = [](uint32_t) { return glm::mat4(1.0f); };
  const auto over = [&](uint32_t slot) { return overlay[slot]; };
  const glm::vec4 tip(2, 0, 0, 1);
  for (float w : {0.25f, 0.5f, 0.75f}) {
    const glm::mat4 child = emulateLayeredMatrix(chain, 1, w, base, over);
    const glm::mat4 expected = turnZ(140 * w, 0) * turnZ(60 * w, 1);
    EXPECT_LT(glm::distance(glm::vec3(child * tip), glm::vec3(expected * tip)), 1e-5f) << w;
    EXPECT_NEAR(glm::degrees(std::atan2(child[0][1], child[0][0])), 200.0f * w, 1e-3f) << w;
  }
  // The ends are the base and the layered matrix; outside the mask, the base.
  EXPECT_EQ(emulateLayeredMatrix(chain, 1, 0.0f, base, over), glm::mat4(1.0f));
  EXPECT_EQ(emulateLayeredMatrix(chain, 1, 1.0f, base, over), overlay[1]);
  EXPECT_EQ(emulateLayeredMatrix(chain, 7, 0.5f, base, over), glm::mat4(1.0f));
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
  // The table holds the slot count and the morph words per mask (none here: no mask moves a
  // target), then each mask's anchors, its parents and its bind origins' bits.
  const size_t slots = arm.slot_anchor.size(), hand_slot = size_t(slotOf("r_hand"));
  const std::vector<int32_t> table = layerMaskTable(Span<const LayerMask>(&arm, 1));
  ASSERT_EQ(table.size(), 2 + 5 * slots);
  EXPECT_EQ(table[0], int32_t(slots));
  EXPECT_EQ(table[1], 0);
  EXPECT_EQ(table[2 + slots + hand_slot], slotOf("r_forearm"));
  for (int k = 0; k < 3; ++k) {
    float f;
    std::memcpy(&f, &table[2 + 2 * slots + 3 * hand_slot + size_t(k)], sizeof f);
    EXPECT_EQ(f, arm.slot_bind_origin[hand_slot][k]);
  }
  // A cycle of parent slots is refused: the shader follows them.
  LayerMask bad = arm;
  bad.slot_parent[size_t(slotOf("r_clavicle"))] = slotOf("r_hand");
  const Status s = bad.validate(b.palette);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("cycle"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace si
