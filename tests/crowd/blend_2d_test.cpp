// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// 2D blend spaces (si/crowd/blend_space.h): the four clips and their weights at a point of the
// grid, and the layer weights that compose to them; all four clips in phase while the point
// moves (each clip's time read back from the records and extra layer records); the drawn pose
// (the records emulated as the shader composes them) against the reference's local-space chain
// (evaluateLayeredChainPose) at points across a cell; crossfades into and out of a 2D blend;
// root motion; jointMatrix; the batcher's layout of the extra layer records; refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "crowd/crowd_test_helpers.h"
#include "si/crowd/blend_space.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/crowd/record_emulation.h"

namespace si {
namespace {

using test::defaultCharacter;
using test::defaultPalette;

// Layer weights composed in order (each a lerp towards its clip) give the clips' shares.
void expectChainComposesToShares(const BlendPoint& b) {
  float total = 0.0f;
  for (uint32_t k = 0; k < b.count; ++k) total += b.shares[k];
  EXPECT_NEAR(total, 1.0f, 1e-6f);
  for (uint32_t k = 0; k < b.count; ++k) {
    float share = b.chain[k];
    for (uint32_t j = k + 1; j < b.count; ++j) share *= 1.0f - b.chain[j];
    EXPECT_NEAR(share, b.shares[k], 1e-6f) << k;
  }
}

TEST(Blend2d, TheCornersAndWeightsFollowThePoint) {
  BlendSpace s;
  s.name = "strafe";
  s.clips = {10, 11, 12, 13, 14, 15};  // 3 x lines, 2 y lines.
  s.positions = {-1.0f, 0.0f, 2.0f};
  s.positions_y = {0.0f, 4.0f};
  const auto expect = [&](float x, float y, std::array<uint32_t, 4> clips,
                          std::array<float, 4> shares) {
    SCOPED_TRACE(testing::Message() << x << ", " << y);
    const BlendPoint b = blendPoint(s, x, y);
    ASSERT_EQ(b.count, 4u);
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(b.clips[k], clips[k]) << k;
      EXPECT_NEAR(b.shares[k], shares[k], 1e-6f) << k;
    }
    expectChainComposesToShares(b);
  };
  expect(-0.5f, 1.0f, {0, 1, 3, 4}, {0.375f, 0.375f, 0.125f, 0.125f});
  expect(1.0f, 3.0f, {1, 2, 4, 5}, {0.125f, 0.125f, 0.375f, 0.375f});
  expect(0.0f, 0.0f, {0, 1, 3, 4}, {0.0f, 1.0f, 0.0f, 0.0f});  // On a grid point: one clip.
  expect(9.0f, 9.0f, {1, 2, 4, 5}, {0.0f, 0.0f, 0.0f, 1.0f});  // Clamped to the corner.
  expect(std::nanf(""), -3.0f, {0, 1, 3, 4}, {1.0f, 0.0f, 0.0f, 0.0f});
  expect(2.0f, 4.0f, {1, 2, 4, 5}, {0.0f, 0.0f, 0.0f, 1.0f});
  // A 1D space: the pair, its weight as the second clip's chain weight.
  BlendSpace line{"line", {0, 1, 2}, {1.0f, 3.0f, 7.0f}, 0};
  for (float p : {0.0f, 2.0f, 3.0f, 4.5f, 9.0f}) {
    const BlendPoint b = blendPoint(line, p);
    const BlendPair pair = blendPair(line.positions, p);
    ASSERT_EQ(b.count, 2u);
    EXPECT_EQ(b.clips[0], pair.lower);
    EXPECT_EQ(b.clips[1], pair.upper);
    EXPECT_EQ(b.chain[1], pair.weight);
    expectChainComposesToShares(b);
  }
  // Validation of the grid.
  const BakedPalette& p = defaultPalette();
  BlendSpace grid{"grid", {0, 1, 2, 3}, {0.0f, 1.0f}, 0, {0.0f, 1.0f}};
  EXPECT_TRUE(grid.is2D());
  EXPECT_TRUE(grid.validate(p, 1).isOk());
  BlendSpace bad = grid;
  bad.clips.pop_back();  // Three clips for four points.
  EXPECT_EQ(bad.validate(p, 1).code(), StatusCode::kInvalidArgument);
  bad = grid;
  bad.positions_y = {1.0f, 1.0f};
  EXPECT_EQ(bad.validate(p, 1).code(), StatusCode::kInvalidArgument);
  EXPECT_NE(bad.validate(p, 1).message().find("y position 1"), std::string::npos);
  bad.positions_y = {0.0f, NAN};
  EXPECT_EQ(bad.validate(p, 1).code(), StatusCode::kInvalidArgument);
  bad = grid;
  bad.positions_y = {0.0f};
  bad.clips = {0, 1};
  EXPECT_EQ(bad.validate(p, 1).code(), StatusCode::kInvalidArgument);
}

// A crowd blending the default palette's four clips on a 2 x 2 grid over the whole body.
struct Blending2d {
  CrowdManager crowd;
  LayerMask body;
  BlendSpace grid;
  uint32_t space = 0;
  InstanceHandle h;
  const BakedPalette* palette = &defaultPalette();

  explicit Blending2d(bool previous_records = false) {
    CrowdDesc cd = test::defaultCrowdDesc();
    cd.previous_records = previous_records;
    EXPECT_TRUE(crowd.init(cd).isOk());
    EXPECT_TRUE(buildFullBodyMask(defaultCharacter().skeleton, *palette, "body", &body).isOk());
    uint32_t mask = 0;
    EXPECT_TRUE(crowd.addLayerMask(body, &mask).isOk());
    const auto clip = [&](const char* name) { return uint32_t(palette->findClip(name)); };
    grid = {"grid",
            {clip("idle"), clip("walk"), clip("run"), clip("wave")},
            {0.0f, 1.0f},
            mask,
            {0.0f, 2.0f}};
    EXPECT_TRUE(crowd.addBlendSpace(grid, &space).isOk());
    InstanceDesc d;
    d.position = glm::dvec3(0.0, 0.0, -6.0);
    d.clip = clip("idle");
    EXPECT_TRUE(crowd.add(d, &h).isOk());
  }
  Camera camera() const { return test::testCamera({0, 1.6, 0}, {0, 1, -6}); }
  // The phase (fraction of its cycle) a frame word pair draws of `clip` (its frames on the
  // uniform grid or at their own times).
  double drawnPhase(uint32_t clip, uint32_t frame_texel, uint32_t fraction_word) const {
    const BakedClip& c = palette->clips[clip];
    const uint32_t frame = (frame_texel - c.first_texel) / palette->layout.frame_stride_texels;
    IntervalMode mode;
    const double f = unpackFraction(fraction_word, &mode);
    if (c.frame_times_seconds.empty())
      return (double(frame) + f) * c.frame_interval_seconds / c.duration_seconds;
    const double t0 = c.frame_times_seconds[frame], t1 = c.frame_times_seconds[frame + 1];
    return (t0 + f * (t1 - t0)) / c.duration_seconds;
  }
  double seconds(uint32_t k) const { return palette->clips[grid.clips[k]].duration_seconds; }
};

TEST(Blend2d, AllFourClipsStayInPhase) {
  Blending2d b;
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, glm::vec2(0.3f, 0.4f), 0.0, 0.1).isOk());
  const glm::vec2 points[] = {{0.3f, 0.4f}, {0.8f, 1.5f},  {0.1f, 0.2f},
                              {0.6f, 1.9f}, {-1.0f, 5.0f}, {0.5f, 1.0f}};
  for (int k = 0; k < 6; ++k) {
    SCOPED_TRACE(k);
    uint32_t space = 9;
    glm::vec2 parameter;
    double before = 0.0, after = 0.0, phase = 0.0;
    ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &before).isOk());
    ASSERT_TRUE(b.crowd.setBlendParameter(b.h, points[k]).isOk());
    ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &after).isOk());
    EXPECT_NEAR(after, before, 1e-9);  // A move keeps the phase.
    EXPECT_EQ(parameter, glm::clamp(points[k], glm::vec2(0.0f), glm::vec2(1.0f, 2.0f)));
    const BlendPoint bp = blendPoint(b.grid, parameter.x, parameter.y);
    double period = 0.0;
    for (uint32_t c = 0; c < 4; ++c) period += double(bp.shares[c]) * b.seconds(bp.clips[c]);
    ASSERT_TRUE(b.crowd.update(0.13, b.camera()).isOk());
    ASSERT_EQ(b.crowd.view().records().size(), 1u);
    ASSERT_EQ(b.crowd.view().extraLayerRecords().size(), 2u);
    ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &phase).isOk());
    EXPECT_NEAR(std::fmod(phase - after + 1.0, 1.0), 0.13 / period, 1e-9);
    // Each clip at the blend's phase; each layer at its chain weight.
    const InstanceRecord& r = b.crowd.view().records()[0];
    const LayerRecord& l = b.crowd.view().layerRecords()[0];
    const LayerRecord* e = b.crowd.view().extraLayerRecords().data();
    const LayerRecord* layer[3] = {&l, e, e + 1};
    EXPECT_NEAR(b.drawnPhase(b.grid.clips[bp.clips[0]], r.frames[0], r.blend[0]), phase, 1e-5);
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(layerWeight(*layer[j]), bp.chain[j + 1], 1e-4) << j;
      if (layerWeight(*layer[j]) > 0.0f) {
        EXPECT_NEAR(
            b.drawnPhase(b.grid.clips[bp.clips[j + 1]], layer[j]->frames[0], layer[j]->fraction),
            phase, 1e-5)
            << j;
      }
    }
    EXPECT_EQ(layerHasExtras(l), bp.chain[2] > 0.0f || bp.chain[3] > 0.0f);
  }
}

// A clock whose cycles a double no longer resolves (a crowd API fuzzer finding: the clock at
// the largest double, where the phase came out NaN): the phase stays in [0, 1), a move keeps it
// there, and the frame updates.
TEST(Blend2d, ThePhaseStaysInItsCycleAtTheLargestClock) {
  Blending2d b;
  // A billion times the clips' speed: the cycles at the largest clock pass a double.
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, glm::vec2(0.5f, 0.5f), 0.0, 0.1, 1e9f).isOk());
  ASSERT_TRUE(b.crowd.advance(std::numeric_limits<double>::max()).isOk());
  uint32_t space = 9;
  glm::vec2 parameter;
  double phase = -1.0;
  ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &phase).isOk());
  EXPECT_TRUE(phase >= 0.0 && phase < 1.0) << phase;
  ASSERT_TRUE(b.crowd.setBlendParameter(b.h, glm::vec2(1.0f, 1.0f)).isOk());
  phase = -1.0;
  ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &phase).isOk());
  EXPECT_TRUE(phase >= 0.0 && phase < 1.0) << phase;
  ASSERT_TRUE(b.crowd.update(0.0, b.camera()).isOk());
  ASSERT_EQ(b.crowd.view().layerRecords().size(), 1u);
}

// Item 2 of the issue for 2D: the drawn pose, emulated from the records as the shader composes
// it, against the reference's local-space chain of the four clips at the phase's times
// (evaluateLayeredChainPose with the chain weights), at points across the cell. What remains is
// the palette's sampling of the clips.
TEST(Blend2d, TheDrawnPoseIsTheLocalSpaceChain) {
  const Character& c = defaultCharacter();
  SkinnedMesh mesh = c.mesh;
  for (glm::vec4& w : mesh.weights) w = dequantizeWeights(quantizeWeights(w));
  std::printf("[ blend 2d ] point         error (units)  of the height\n");
  double worst = 0.0;
  for (glm::vec2 at : {glm::vec2(0.0f, 0.0f), glm::vec2(0.25f, 0.5f), glm::vec2(0.5f, 1.0f),
                       glm::vec2(0.9f, 0.3f), glm::vec2(0.6f, 1.7f), glm::vec2(1.0f, 2.0f)}) {
    Blending2d b;
    ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, at, 0.0, 0.37).isOk());
    ASSERT_TRUE(b.crowd.update(0.071, b.camera()).isOk());  // Off the 30 Hz grid.
    ASSERT_EQ(b.crowd.view().records().size(), 1u);
    uint32_t space = 0;
    glm::vec2 parameter;
    double phase = 0.0;
    ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &phase).isOk());
    const BakedPalette& p = *b.palette;
    std::vector<glm::mat4> m(p.skeleton_to_palette.size(), glm::mat4(1.0f));
    for (size_t j = 0; j < m.size(); ++j)
      if (p.skeleton_to_palette[j] >= 0)
        m[j] = emulateLayeredRecordMatrix(p, b.crowd.view().records()[0],
                                          b.crowd.view().layerRecords()[0],
                                          b.crowd.view().extraLayerRecords(), b.crowd.layerMasks(),
                                          uint32_t(p.skeleton_to_palette[j]));
    std::vector<glm::vec3> drawn(mesh.positions.size());
    ASSERT_TRUE(emulateSkinning(mesh, m, drawn, {}).isOk());
    const BlendPoint bp = blendPoint(b.grid, parameter.x, parameter.y);
    const auto clipOf = [&](uint32_t k) -> const Clip& {
      return c.clips[size_t(c.findClip(p.clips[b.grid.clips[bp.clips[k]]].name))];
    };
    std::vector<LayerSample> layers;
    for (uint32_t k = 1; k < 4; ++k)
      layers.push_back({&clipOf(k), phase * clipOf(k).duration_seconds, double(bp.chain[k])});
    ReferencePose pose;
    ASSERT_TRUE(evaluateLayeredChainPose(c.skeleton, clipOf(0), phase * clipOf(0).duration_seconds,
                                         layers, b.body, &pose)
                    .isOk());
    std::vector<glm::dvec3> reference(mesh.positions.size());
    ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, reference, {}, {}).isOk());
    double e = 0.0;
    for (size_t v = 0; v < drawn.size(); ++v)
      e = std::max(e, glm::length(glm::dvec3(drawn[v]) - reference[v]));
    std::printf("[ blend 2d ] (%4.2f, %4.2f)  %13.3g  %12.3g\n", double(at.x), double(at.y), e,
                e / c.height());
    worst = std::max(worst, e);
  }
  // The palette's sampling of the clips at 30 Hz (the 1D blend's error is 6.5e-3 units).
  EXPECT_GT(worst, 0.0);
  EXPECT_LT(worst, 0.02);
}

// Into a 2D blend from a clip, every layer's weight rises from 0 over the span; a plain overlay
// or stopOverlay fades the extra layers out with it; jointMatrix draws what the records draw.
TEST(Blend2d, CrossfadesIntoAndOutOfA2dBlend) {
  Blending2d b;
  ASSERT_TRUE(b.crowd.update(0.1, b.camera()).isOk());
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, glm::vec2(0.5f, 1.0f), 0.4).isOk());
  ASSERT_TRUE(b.crowd.update(0.2, b.camera()).isOk());  // Half-way.
  const BlendPoint bp = blendPoint(b.grid, 0.5f, 1.0f);
  EXPECT_NEAR(layerWeight(b.crowd.view().layerRecords()[0]), 0.5f * bp.chain[1], 1e-4);
  EXPECT_NEAR(layerWeight(b.crowd.view().extraLayerRecords()[0]), 0.5f * bp.chain[2], 1e-4);
  EXPECT_NEAR(layerWeight(b.crowd.view().extraLayerRecords()[1]), 0.5f * bp.chain[3], 1e-4);
  // jointMatrix: the emulated records' matrix placed in the world.
  const BakedPalette& p = *b.palette;
  const uint32_t hand = uint32_t(defaultCharacter().skeleton.findJoint("r_hand"));
  glm::dmat4 joint;
  ASSERT_TRUE(b.crowd.jointMatrix(b.h, hand, &joint).isOk());
  const glm::mat4 drawn =
      emulateLayeredRecordMatrix(p, b.crowd.view().records()[0], b.crowd.view().layerRecords()[0],
                                 b.crowd.view().extraLayerRecords(), b.crowd.layerMasks(),
                                 uint32_t(p.skeleton_to_palette[hand]));
  InstanceDesc d;
  ASSERT_TRUE(b.crowd.get(b.h, &d).isOk());
  const glm::dmat4 world = glm::translate(glm::dmat4(1.0), d.position) * glm::dmat4(drawn);
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 3; ++row) EXPECT_NEAR(joint[col][row], world[col][row], 1e-5);
  // Out: stopOverlay fades every layer to 0 over its span.
  ASSERT_TRUE(b.crowd.update(0.2, b.camera()).isOk());
  ASSERT_TRUE(b.crowd.stopOverlay(b.h, 0.5).isOk());
  ASSERT_TRUE(b.crowd.update(0.25, b.camera()).isOk());
  EXPECT_NEAR(layerWeight(b.crowd.view().extraLayerRecords()[1]), 0.5f * bp.chain[3], 1e-4);
  ASSERT_TRUE(b.crowd.update(0.3, b.camera()).isOk());
  for (const LayerRecord& e : b.crowd.view().extraLayerRecords()) EXPECT_EQ(layerWeight(e), 0.0f);
  EXPECT_FALSE(layerHasExtras(b.crowd.view().layerRecords()[0]));
  // A plain overlay replaces a 2D blend: the extra layers fade out over its span.
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, glm::vec2(0.5f, 1.0f), 0.0).isOk());
  ASSERT_TRUE(b.crowd.playOverlay(b.h, b.grid.clips[3], 0, 1.0f, 0.5).isOk());
  ASSERT_TRUE(b.crowd.update(0.25, b.camera()).isOk());
  EXPECT_NEAR(layerWeight(b.crowd.view().extraLayerRecords()[1]), 0.5f * bp.chain[3], 1e-4);
  ASSERT_TRUE(b.crowd.update(0.3, b.camera()).isOk());
  EXPECT_EQ(layerWeight(b.crowd.view().extraLayerRecords()[1]), 0.0f);
  // A 1D space's blend draws no extra layers.
  BlendSpace line{"line", {b.grid.clips[0], b.grid.clips[1]}, {0.0f, 1.0f}, 0};
  uint32_t line_id = 0;
  ASSERT_TRUE(b.crowd.addBlendSpace(line, &line_id).isOk());
  ASSERT_TRUE(b.crowd.playBlend(b.h, line_id, 0.5f, 0.0).isOk());
  ASSERT_TRUE(b.crowd.update(0.1, b.camera()).isOk());
  EXPECT_FALSE(layerHasExtras(b.crowd.view().layerRecords()[0]));
  EXPECT_NEAR(layerWeight(b.crowd.view().layerRecords()[0]), 0.5f, 1e-4);
}

// Root motion of a 2D blend travels as the clips blend: at a grid point as that clip alone.
TEST(Blend2d, RootMotionTravelsAsTheClipsBlend) {
  const BakedPalette& p = test::movingPalette();
  const uint32_t straight = uint32_t(p.findClip("walk_forward")),
                 turning = uint32_t(p.findClip("walk_turn_left"));
  const auto travel = [&](glm::vec2 at, int alone) {
    CrowdManager crowd;
    CrowdDesc cd = test::defaultCrowdDesc();
    cd.palette = &p;
    EXPECT_TRUE(crowd.init(cd).isOk());
    LayerMask body;
    EXPECT_TRUE(buildFullBodyMask(test::movingCharacter().skeleton, p, "body", &body).isOk());
    uint32_t mask = 0, space = 0;
    EXPECT_TRUE(crowd.addLayerMask(body, &mask).isOk());
    EXPECT_TRUE(
        crowd
            .addBlendSpace(
                {"grid", {straight, turning, turning, straight}, {0.0f, 1.0f}, mask, {0.0f, 1.0f}},
                &space)
            .isOk());
    InstanceDesc d;
    d.root_motion = true;
    d.clip = alone >= 0 ? uint32_t(alone) : straight;
    InstanceHandle h;
    EXPECT_TRUE(crowd.add(d, &h).isOk());
    if (alone < 0) {
      EXPECT_TRUE(crowd.playBlend(h, space, at, 0.0).isOk());
    }
    const Camera camera = test::testCamera({0, 1.6, 6}, {0, 1, 0});
    for (int k = 0; k < 10; ++k) EXPECT_TRUE(crowd.update(0.05, camera).isOk());
    EXPECT_TRUE(crowd.get(h, &d).isOk());
    return d.position;
  };
  const glm::dvec3 a = travel({}, int(straight)), t = travel({}, int(turning));
  ASSERT_GT(glm::length(a - t), 0.05);
  EXPECT_LT(glm::length(travel({1.0f, 0.0f}, -1) - t), 1e-6);
  EXPECT_LT(glm::length(travel({1.0f, 1.0f}, -1) - a), 1e-6);
  EXPECT_LT(glm::length(travel({0.0f, 1.0f}, -1) - t), 1e-6);
  // The cell's centre: half each; near the mean of the two.
  EXPECT_LT(glm::length(travel({0.5f, 0.5f}, -1) - 0.5 * (a + t)), 0.25 * glm::length(a - t));
}

// The batcher lays each slot's two extra layer records out beside its layer slot, with the
// previous ones' fallbacks; refusals name what is wrong.
TEST(Blend2d, TheBatcherLaysOutTheExtraLayers) {
  Blending2d b(true);
  InstanceDesc d;
  d.position = glm::dvec3(1.0, 0.0, -6.0);
  InstanceHandle second;
  ASSERT_TRUE(b.crowd.add(d, &second).isOk());
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, glm::vec2(0.4f, 0.7f), 0.0).isOk());
  ASSERT_TRUE(b.crowd.update(0.1, b.camera()).isOk());
  InstanceBatcher batcher;
  BatchLimits limits;
  limits.max_uniform_block_size_bytes = 16384;
  ASSERT_TRUE(batcher.init(limits).isOk());
  std::vector<uint8_t> records(batcher.recordBufferBound(b.crowd.view()));
  std::vector<DrawBatch> draws;
  ASSERT_TRUE(batcher.build(b.crowd.view(), records, &draws).isOk());
  std::vector<uint8_t> extras(batcher.extraLayerBufferBound(b.crowd.view()));
  EXPECT_EQ(extras.size(), batcher.layerBufferBound(b.crowd.view()) * 2);
  std::vector<uint8_t> small(extras.size() - 1);
  EXPECT_EQ(batcher.buildExtraLayers(b.crowd.view(), small).code(), StatusCode::kCountMismatch);
  ASSERT_TRUE(batcher.buildExtraLayers(b.crowd.view(), extras).isOk());
  // Each slot's records are those of the instance whose record sits in the slot.
  const auto extrasOf = [&](const std::vector<uint8_t>& bytes, const DrawBatch& batch,
                            uint32_t slot, LayerRecord out[2]) {
    std::memcpy(out, bytes.data() + (batch.layer_byte_offset / kLayerRecordSize + slot) * 32, 32);
  };
  size_t checked = 0;
  for (const DrawBatch& batch : draws)
    for (uint32_t k = 0; k < batch.instance_count; ++k) {
      InstanceRecord r;
      std::memcpy(&r, records.data() + batch.byte_offset + k * kInstanceRecordSize, sizeof r);
      for (size_t i = 0; i < b.crowd.view().records().size(); ++i)
        if (std::memcmp(&r, &b.crowd.view().records()[i], sizeof r) == 0) {
          LayerRecord got[2];
          extrasOf(extras, batch, k, got);
          EXPECT_EQ(std::memcmp(got, &b.crowd.view().extraLayerRecords()[i * 2], 32), 0);
          ++checked;
        }
    }
  EXPECT_GE(checked, 2u);
  // Previous: after moving the point, each slot holds the previous update's extra records.
  const std::vector<LayerRecord> before(b.crowd.view().extraLayerRecords().begin(),
                                        b.crowd.view().extraLayerRecords().end());
  ASSERT_TRUE(b.crowd.setBlendParameter(b.h, glm::vec2(0.9f, 1.8f)).isOk());
  ASSERT_TRUE(b.crowd.update(0.1, b.camera()).isOk());
  ASSERT_EQ(b.crowd.view().previousExtraLayerRecords().size(), before.size());
  EXPECT_EQ(std::memcmp(b.crowd.view().previousExtraLayerRecords().data(), before.data(),
                        before.size() * sizeof(LayerRecord)),
            0);
  ASSERT_TRUE(b.crowd.update(0.0, b.camera()).isOk());
  ASSERT_TRUE(batcher.build(b.crowd.view(), records, &draws).isOk());
  std::vector<uint8_t> previous(extras.size());
  ASSERT_TRUE(batcher.buildPreviousExtraLayers(b.crowd.view(), previous).isOk());
  ASSERT_TRUE(batcher.buildExtraLayers(b.crowd.view(), extras).isOk());
  // A second update at the same clock: the previous records are this one's.
  EXPECT_EQ(previous, extras);
  // Refusals: without a 2D space no extra layer records are written.
  CrowdManager plain;
  ASSERT_TRUE(plain.init(test::defaultCrowdDesc()).isOk());
  ASSERT_TRUE(plain.update(0.0, b.camera()).isOk());
  EXPECT_TRUE(plain.view().extraLayerRecords().empty());
  EXPECT_EQ(batcher.buildExtraLayers(plain.view(), extras).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(batcher.buildPreviousExtraLayers(plain.view(), extras).code(),
            StatusCode::kInvalidArgument);
  std::vector<GpuOverlayState> exported;
  CrowdExport(plain).extraLayers(&exported);
  EXPECT_TRUE(exported.empty());
  CrowdExport(b.crowd).extraLayers(&exported);
  ASSERT_EQ(exported.size(), size_t(b.crowd.size()) * kExtraLayerRecords);
}

TEST(Blend2d, RefusalsNameWhatIsWrong) {
  Blending2d b;
  EXPECT_EQ(b.crowd.playBlend(b.h, b.space, glm::vec2(0.0f, NAN), 0.0).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(b.crowd.setBlendParameter(b.h, glm::vec2(0.5f)).code(),
            StatusCode::kInvalidArgument);  // None plays.
  ASSERT_TRUE(b.crowd.playBlend(b.h, b.space, glm::vec2(0.5f), 0.0).isOk());
  EXPECT_EQ(b.crowd.setBlendParameter(b.h, glm::vec2(INFINITY, 0.0f)).code(),
            StatusCode::kInvalidArgument);
  uint32_t space = 0;
  double phase = 0.0;
  EXPECT_EQ(b.crowd.blendState(b.h, &space, nullptr, &phase).code(), StatusCode::kInvalidArgument);
  // setBlendParameter(h, x) keeps the instance's y.
  ASSERT_TRUE(b.crowd.setBlendParameter(b.h, glm::vec2(0.2f, 1.5f)).isOk());
  ASSERT_TRUE(b.crowd.setBlendParameter(b.h, 0.7f).isOk());
  glm::vec2 parameter;
  ASSERT_TRUE(b.crowd.blendState(b.h, &space, &parameter, &phase).isOk());
  EXPECT_EQ(parameter, glm::vec2(0.7f, 1.5f));
  ASSERT_TRUE(b.crowd.remove(b.h).isOk());
  EXPECT_EQ(b.crowd.setBlendParameter(b.h, glm::vec2(0.5f)).code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace si
