// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Blend spaces (si/crowd/blend_space.h): the pair and weight at a parameter; both clips in
// phase while the parameter moves (each clip's time, read back from the records, at the same
// fraction of its cycle); the drawn pose (the records emulated as the shader computes them)
// against the reference's local-space blend, per weight; crossfades into and out of a blend;
// root motion travelling as the clips blend; refusals.
#include "si/crowd/blend_space.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "crowd/crowd_test_helpers.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/record_emulation.h"

namespace si {
namespace {

using test::defaultCharacter;
using test::defaultPalette;

TEST(BlendSpace, ThePairAndWeightFollowTheParameter) {
  const std::vector<float> at = {1.0f, 3.0f, 7.0f};
  const auto expect = [&](float p, uint32_t lower, uint32_t upper, float w) {
    const BlendPair b = blendPair(at, p);
    EXPECT_EQ(b.lower, lower) << p;
    EXPECT_EQ(b.upper, upper) << p;
    EXPECT_FLOAT_EQ(b.weight, w) << p;
  };
  expect(-5.0f, 0, 1, 0.0f);
  expect(1.0f, 0, 1, 0.0f);
  expect(2.0f, 0, 1, 0.5f);
  expect(3.0f, 0, 1, 1.0f);
  expect(4.0f, 1, 2, 0.25f);
  expect(7.0f, 1, 2, 1.0f);
  expect(70.0f, 1, 2, 1.0f);
  expect(std::nanf(""), 0, 1, 0.0f);
  EXPECT_DOUBLE_EQ(blendPeriod(1.0, 0.6, 0.25f), 0.9);
  // The full-body mask holds every palette slot; those hanging from no stored joint (below the
  // unweighted root) take the model as their anchor.
  const BakedPalette& p = defaultPalette();
  LayerMask body;
  ASSERT_TRUE(buildFullBodyMask(defaultCharacter().skeleton, p, "body", &body).isOk());
  EXPECT_EQ(body.joints.size(), defaultCharacter().skeleton.jointCount());
  for (uint32_t slot = 0; slot < p.palette_joints.size(); ++slot)
    EXPECT_TRUE(body.contains(slot)) << slot;
  EXPECT_EQ(body.slot_anchor[uint32_t(
                p.skeleton_to_palette[size_t(defaultCharacter().skeleton.findJoint("pelvis"))])],
            LayerMask::kModelAnchor);
  EXPECT_EQ(buildFullBodyMask(defaultCharacter().skeleton, p, "body", nullptr).code(),
            StatusCode::kInvalidArgument);
  // Validation.
  BlendSpace s{"locomotion", {0, 1}, {0.0f, 1.0f}, 0};
  EXPECT_TRUE(s.validate(p, 1).isOk());
  EXPECT_EQ(s.validate(p, 0).code(), StatusCode::kInvalidArgument);  // No such mask.
  BlendSpace bad = s;
  bad.positions = {1.0f, 1.0f};
  EXPECT_EQ(bad.validate(p, 1).code(), StatusCode::kInvalidArgument);
  bad = s;
  bad.positions = {0.0f, INFINITY};
  EXPECT_EQ(bad.validate(p, 1).code(), StatusCode::kInvalidArgument);
  bad = s;
  bad.clips = {0, uint32_t(p.clips.size())};
  EXPECT_EQ(bad.validate(p, 1).code(), StatusCode::kInvalidArgument);
  bad = s;
  bad.clips = {0};
  bad.positions = {0.0f};
  EXPECT_EQ(bad.validate(p, 1).code(), StatusCode::kInvalidArgument);
  bad = s;
  bad.name.clear();
  EXPECT_EQ(bad.validate(p, 1).code(), StatusCode::kInvalidArgument);
}

struct Blending {
  CrowdManager crowd;
  LayerMask body;
  uint32_t space = 0, walk = 0, run = 0, idle = 0;
  InstanceHandle h;
  const BakedPalette* palette = &defaultPalette();

  explicit Blending(const BakedPalette& p = defaultPalette(), const char* lower = "walk",
                    const char* upper = "run", bool root_motion = false) {
    palette = &p;
    CrowdDesc cd = test::defaultCrowdDesc();
    cd.palette = &p;
    EXPECT_TRUE(crowd.init(cd).isOk());
    EXPECT_TRUE(buildFullBodyMask(defaultCharacter().skeleton, p, "body", &body).isOk());
    uint32_t mask = 0;
    EXPECT_TRUE(crowd.addLayerMask(body, &mask).isOk());
    walk = uint32_t(p.findClip(lower));
    run = uint32_t(p.findClip(upper));
    idle = uint32_t(p.findClip("idle"));
    EXPECT_TRUE(
        crowd.addBlendSpace({"locomotion", {walk, run}, {1.0f, 4.0f}, mask}, &space).isOk());
    InstanceDesc d;
    d.position = glm::dvec3(0.0, 0.0, -6.0);
    d.clip = idle;
    d.root_motion = root_motion;
    EXPECT_TRUE(crowd.add(d, &h).isOk());
  }
  Camera camera() const { return test::testCamera({0, 1.6, 0}, {0, 1, -6}); }
  // The clip-local time the record (layer record: `layer`) draws of `clip`, from its frames.
  double drawnTime(uint32_t clip, uint32_t frame_texel, uint32_t fraction_word) const {
    const BakedClip& c = palette->clips[clip];
    EXPECT_TRUE(c.frame_times_seconds.empty());  // A uniform grid: time from frame and fraction.
    const uint32_t frame = (frame_texel - c.first_texel) / palette->layout.frame_stride_texels;
    IntervalMode mode;
    const float f = unpackFraction(fraction_word, &mode);
    return (double(frame) + double(f)) * c.frame_interval_seconds;
  }
};

// Both clips at the same fraction of their cycles as the parameter moves; the phase continuous
// across each change; the weight the parameter's.
TEST(BlendSpace, BothClipsStayInPhase) {
  Blending b;
  const double walk_s = b.palette->clips[b.walk].duration_seconds;
  const double run_s = b.palette->clips[b.run].duration_seconds;
  ASSERT_NE(walk_s, run_s);  // Otherwise phase sync is trivial.
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, 1.6f, 0.0, 0.1).isOk());
  const float parameters[] = {1.6f, 2.5f, 3.7f, 1.2f, 4.0f, 0.0f, 2.9f};
  double last_phase = 0.1;
  for (int k = 0; k < 7; ++k) {
    uint32_t space = 9;
    glm::vec2 parameter(0.0f);
    double before = 0.0, after = 0.0;
    ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &before).isOk());
    ASSERT_TRUE(b.crowd.setBlendParameter(b.h, parameters[k]).isOk());
    ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &after).isOk());
    EXPECT_EQ(space, b.space);
    EXPECT_NEAR(after, before, 1e-9) << k;  // A change keeps the phase.
    EXPECT_FLOAT_EQ(parameter.x, std::clamp(parameters[k], 1.0f, 4.0f));
    const float w = std::clamp((parameters[k] - 1.0f) / 3.0f, 0.0f, 1.0f);
    const double period = walk_s + (run_s - walk_s) * w;
    ASSERT_TRUE(b.crowd.update(0.13, b.camera()).isOk());
    ASSERT_EQ(b.crowd.view().records().size(), 1u);
    ASSERT_EQ(b.crowd.view().layerRecords().size(), 1u);
    const InstanceRecord& r = b.crowd.view().records()[0];
    const LayerRecord& l = b.crowd.view().layerRecords()[0];
    EXPECT_NEAR(layerWeight(l), w, 1e-4);
    double phase = 0.0;
    ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &phase).isOk());
    // The phase advanced 0.13 s over the blended period.
    const double advanced = std::fmod(phase - after + 1.0, 1.0);
    EXPECT_NEAR(advanced, 0.13 / period, 1e-9) << k;
    const double walk_phase = b.drawnTime(b.walk, r.frames[0], r.blend[0]) / walk_s;
    const double run_phase = b.drawnTime(b.run, l.frames[0], l.fraction) / run_s;
    EXPECT_NEAR(walk_phase, phase, 1e-5) << k;
    EXPECT_NEAR(run_phase, phase, 1e-5) << k;
    last_phase = phase;
  }
  EXPECT_GT(last_phase, 0.0);
}

// Item 2 of the issue: the drawn pose, emulated from the records as the shader computes it,
// against the reference's local-space blend of the two clips at the phase's times (each joint's
// local rotation slerped, translation and scale lerped: evaluateLayeredPose on the full mask).
// What remains is the palette's sampling of both clips, at every weight.
TEST(BlendSpace, TheDrawnPoseIsTheLocalSpaceBlend) {
  const Character& c = defaultCharacter();
  const Clip& walk = c.clips[size_t(c.findClip("walk"))];
  const Clip& run = c.clips[size_t(c.findClip("run"))];
  SkinnedMesh mesh = c.mesh;
  for (glm::vec4& w : mesh.weights) w = dequantizeWeights(quantizeWeights(w));
  std::printf("[ blend    ] weight  error (units)  of the height\n");
  double worst = 0.0;
  for (float w : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
    Blending b;
    ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, 1.0f + 3.0f * w, 0.0, 0.37).isOk());
    ASSERT_TRUE(b.crowd.update(0.071, b.camera()).isOk());  // Off the 30 Hz grid.
    ASSERT_EQ(b.crowd.view().records().size(), 1u);
    uint32_t space = 0;
    glm::vec2 parameter(0.0f);
    double phase = 0.0;
    ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &phase).isOk());
    const BakedPalette& p = *b.palette;
    std::vector<glm::mat4> m(p.skeleton_to_palette.size(), glm::mat4(1.0f));
    for (size_t j = 0; j < m.size(); ++j)
      if (p.skeleton_to_palette[j] >= 0)
        m[j] = emulateLayeredRecordMatrix(p, b.crowd.view().records()[0],
                                          b.crowd.view().layerRecords()[0], b.crowd.layerMasks(),
                                          uint32_t(p.skeleton_to_palette[j]));
    std::vector<glm::vec3> drawn(mesh.positions.size());
    ASSERT_TRUE(emulateSkinning(mesh, m, drawn, {}).isOk());
    ReferencePose pose;
    ASSERT_TRUE(evaluateLayeredPose(c.skeleton, walk, phase * walk.duration_seconds, run,
                                    phase * run.duration_seconds, b.body, w, &pose)
                    .isOk());
    std::vector<glm::dvec3> reference(mesh.positions.size());
    ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, reference, {}, {}).isOk());
    double e = 0.0;
    for (size_t v = 0; v < drawn.size(); ++v)
      e = std::max(e, glm::length(glm::dvec3(drawn[v]) - reference[v]));
    std::printf("[ blend    ] %6.2f  %13.3g  %12.3g\n", double(w), e, e / c.height());
    RecordProperty("error_units_at_" + std::to_string(int(w * 100)), std::to_string(e));
    worst = std::max(worst, e);
  }
  // The palette's sampling of the two clips at 30 Hz (each about 5e-3 to 7e-3 units alone).
  EXPECT_GT(worst, 0.0);
  EXPECT_LT(worst, 0.02);
}

// Into a blend from a clip: the clip crossfades to the lower clip and the overlay's weight
// rises to the blend's over the span; out of it, crossfade() fades the upper clip out and the
// instance plays the clip alone.
TEST(BlendSpace, CrossfadesIntoAndOutOfABlend) {
  Blending b;
  ASSERT_TRUE(b.crowd.update(0.1, b.camera()).isOk());
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, 2.5f, 0.4).isOk());  // Weight 0.5 over 0.4 s.
  ASSERT_TRUE(b.crowd.update(0.2, b.camera()).isOk());
  const InstanceRecord& mid = b.crowd.view().records()[0];
  float fade = 0.0f;
  std::memcpy(&fade, &mid.blend[2], 4);
  EXPECT_NEAR(fade, 0.5f, 1e-4);  // The crossfade half-way (to the walk).
  EXPECT_NEAR(layerWeight(b.crowd.view().layerRecords()[0]), 0.25f, 1e-4);
  // Mid-fade to weight 1: the weight goes on from 0.25 towards 1 over the 0.2 s left.
  ASSERT_TRUE(b.crowd.setBlendParameter(b.h, 4.0f).isOk());
  ASSERT_TRUE(b.crowd.update(0.1, b.camera()).isOk());
  EXPECT_NEAR(layerWeight(b.crowd.view().layerRecords()[0]), 0.625f, 1e-4);
  ASSERT_TRUE(b.crowd.update(0.2, b.camera()).isOk());
  EXPECT_EQ(b.crowd.view().records()[0].blend[2], 0u);  // The crossfade is over.
  EXPECT_NEAR(layerWeight(b.crowd.view().layerRecords()[0]), 1.0f, 1e-4);
  // Out: to the idle over 0.5 s.
  ASSERT_TRUE(b.crowd.crossfade(b.h, b.idle, 0.5).isOk());
  uint32_t space = 0;
  glm::vec2 parameter(0.0f);
  double phase = 0.0;
  EXPECT_EQ(b.crowd.blendState(b.h, &space, &parameter, &phase).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(b.crowd.setBlendParameter(b.h, 2.0f).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(b.crowd.update(0.25, b.camera()).isOk());
  EXPECT_NEAR(layerWeight(b.crowd.view().layerRecords()[0]), 0.5f, 1e-4);
  ASSERT_TRUE(b.crowd.update(0.3, b.camera()).isOk());
  EXPECT_EQ(layerWeight(b.crowd.view().layerRecords()[0]), 0.0f);
  InstanceDesc d;
  ASSERT_TRUE(b.crowd.get(b.h, &d).isOk());
  EXPECT_EQ(d.clip, b.idle);
  // play() ends a blend at once; so does a new overlay (the lower clip plays on).
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, 3.0f, 0.0).isOk());
  ASSERT_TRUE(b.crowd.play(b.h, b.idle, 0.0, 1.0f).isOk());
  ASSERT_TRUE(b.crowd.update(0.01, b.camera()).isOk());
  EXPECT_EQ(layerWeight(b.crowd.view().layerRecords()[0]), 0.0f);
}

// Root motion travels as the clips blend: at either end of the space the instance travels as
// the clip alone does, and between them in between.
TEST(BlendSpace, RootMotionTravelsAsTheClipsBlend) {
  const auto travel = [](float parameter, bool blend) {
    Blending b(test::movingPalette(), "walk_forward", "walk_turn_left", true);
    if (blend) {
      EXPECT_TRUE(b.crowd.playBlend(b.h, b.space, parameter, 0.0).isOk());
    } else {
      EXPECT_TRUE(b.crowd.play(b.h, parameter < 2.0f ? b.walk : b.run, 0.0, 1.0f).isOk());
    }
    for (int k = 0; k < 10; ++k) EXPECT_TRUE(b.crowd.update(0.05, b.camera()).isOk());
    InstanceDesc d;
    EXPECT_TRUE(b.crowd.get(b.h, &d).isOk());
    return d.position - glm::dvec3(0.0, 0.0, -6.0);
  };
  // The two clips of the moving character have one length: the phase runs as each alone.
  EXPECT_LT(glm::length(travel(1.0f, true) - travel(1.0f, false)), 1e-6);
  EXPECT_LT(glm::length(travel(4.0f, true) - travel(4.0f, false)), 1e-6);
  const glm::dvec3 straight = travel(1.0f, false), turning = travel(4.0f, false),
                   half = travel(2.5f, true);
  EXPECT_GT(glm::length(straight - turning), 0.05);
  // Half-way: the translation's per-step mix of the two, near their mean.
  EXPECT_LT(glm::length(half - 0.5 * (straight + turning)), 0.25 * glm::length(straight - turning));
}

// A speed so large that a clip's rate over the blended period would pass a float is held at
// the largest float: every playback speed stays finite (the records too).
TEST(BlendSpace, HugeSpeedsStayFinite) {
  Blending b;
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, 1.0f, 0.0, 0.0, 3e38f).isOk());
  ASSERT_TRUE(b.crowd.setBlendParameter(b.h, 4.0f).isOk());
  InstanceDesc d;
  ASSERT_TRUE(b.crowd.get(b.h, &d).isOk());
  EXPECT_TRUE(std::isfinite(d.speed));
  ASSERT_TRUE(b.crowd.update(0.01, b.camera()).isOk());
  for (const auto& row : b.crowd.view().records()[0].world_rows)
    for (float v : row) EXPECT_TRUE(std::isfinite(v));
}

TEST(BlendSpace, RefusalsNameWhatIsWrong) {
  Blending b;
  EXPECT_EQ(b.crowd.playBlend(b.h, 7, 1.0f, 0.0).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(b.crowd.playBlend(b.h, b.space, std::nanf(""), 0.0).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(b.crowd.playBlend(b.h, b.space, 1.0f, -1.0).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(b.crowd.playBlend(b.h, b.space, 1.0f, 0.0, 0.0, -1.0f).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(b.crowd.setBlendParameter(b.h, 2.0f).code(),
            StatusCode::kInvalidArgument);  // None plays.
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, 1.0f, 0.0).isOk());
  EXPECT_EQ(b.crowd.setBlendParameter(b.h, INFINITY).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(b.crowd.blendState(b.h, nullptr, nullptr, nullptr).code(),
            StatusCode::kInvalidArgument);
  BlendSpace s = b.crowd.blendSpaces()[0];
  s.mask = 5;
  EXPECT_EQ(b.crowd.addBlendSpace(s, nullptr).code(), StatusCode::kInvalidArgument);
  s.mask = 0;
  for (uint32_t k = 1; k < CrowdManager::kMaxBlendSpaces; ++k)
    ASSERT_TRUE(b.crowd.addBlendSpace(s, nullptr).isOk());
  EXPECT_EQ(b.crowd.addBlendSpace(s, nullptr).code(), StatusCode::kLimitExceeded);
  ASSERT_TRUE(b.crowd.remove(b.h).isOk());
  EXPECT_EQ(b.crowd.playBlend(b.h, b.space, 1.0f, 0.0).code(), StatusCode::kNotFound);
  EXPECT_EQ(b.crowd.setBlendParameter(b.h, 1.0f).code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace si
