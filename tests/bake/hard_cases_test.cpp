// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The baker's hard cases. Each asserts no NaN or Inf in the palette or the emulation, and an
// error within its named bound (a fraction of the character's height unless stated).
#include <gtest/gtest.h>

#include <cmath>

#include "bake/bake_test_helpers.h"
#include "si/bake/animation_baker.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {
using test::axisAngleF;
using test::blankClip;
using test::chainCharacter;

constexpr double kPi = 3.14159265358979323846;
// Named bounds (docs/accuracy.md lists them).
constexpr double kSmoothMotionBound = 1e-3;      // 90 deg/s at 30 Hz on a 3-unit chain.
constexpr double kExactBound = 1e-6;             // Cases the palette represents exactly.
constexpr double kLargeTangentBound = 5e-3;      // CUBICSPLINE with 50x tangents, 60 Hz.
constexpr double kLongClipBound = 1e-3;          // 10 minutes at 60 fps.

BakeDesc fixedRate(float hz, PaletteFormat format = PaletteFormat::kMatrix3x4F32) {
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = hz;
  d.format = format;
  return d;
}

// Bakes, checks every texel and the emulated mesh at many times for finiteness, returns the
// report's max error as a fraction of the height.
double bakeAndCheck(const Character& c, const BakeDesc& d, BakeReport* report_out = nullptr,
                    BakedPalette* palette_out = nullptr) {
  BakedPalette p;
  BakeReport r;
  const Status s = bakePalette(c, d, &p, &r);
  EXPECT_TRUE(s.isOk()) << s.toString();
  if (!s.isOk()) return 1e30;
  std::vector<glm::mat4> mats(c.skeleton.jointCount());
  std::vector<glm::vec3> pos(c.mesh.vertexCount()), nrm(c.mesh.vertexCount());
  for (uint32_t clip = 0; clip < p.clips.size(); ++clip) {
    for (uint32_t f = 0; f < p.clips[clip].frame_count; f += 1 + p.clips[clip].frame_count / 64)
      for (uint32_t slot = 0; slot < p.palette_joints.size(); ++slot)
        EXPECT_TRUE(isFinite(decodeJoint(p, clip, f, slot))) << "frame " << f;
    for (int i = 0; i <= 40; ++i) {
      const double t = p.clips[clip].duration_seconds * i / 40.0;
      EXPECT_TRUE(emulateSkinningMatrices(p, clip, sampleFrames(p.clips[clip], t), mats).isOk());
      EXPECT_TRUE(emulateSkinning(c.mesh, mats, pos, nrm).isOk());
      for (size_t v = 0; v < pos.size(); ++v) {
        const bool finite = isFinite(glm::vec4(pos[v], 1.0f)) && isFinite(glm::vec4(nrm[v], 1.0f));
        EXPECT_TRUE(finite) << "t=" << t << " vertex " << v;
        if (!finite) return 1e30;
      }
    }
  }
  EXPECT_TRUE(std::isfinite(r.max_error_units));
  if (report_out) *report_out = r;
  if (palette_out) *palette_out = p;
  return r.max_error_ratio;
}

TEST(HardCases, AntipodalQuaternionKeys) {
  Character c = chainCharacter(3);
  Clip clip = blankClip(c, "antipodal", 1.0f);
  clip.joint_tracks[0].rotation.times_seconds = {0.0f, 1.0f};
  // -q(90 deg) is the same rotation as q(90 deg): the short way is 90 degrees, not 270.
  clip.joint_tracks[0].rotation.values = {glm::quat(1, 0, 0, 0), -axisAngleF(kPi / 2, {0, 0, 1})};
  c.clips.push_back(clip);
  for (PaletteFormat f : {PaletteFormat::kMatrix3x4F32, PaletteFormat::kQuatTranslationF32})
    EXPECT_LE(bakeAndCheck(c, fixedRate(30, f)), kSmoothMotionBound) << paletteFormatName(f);
}

TEST(HardCases, NonUnitQuaternionKeys) {
  Character c = chainCharacter(3);
  Clip clip = blankClip(c, "non_unit", 1.0f);
  clip.joint_tracks[1].rotation.times_seconds = {0.0f, 0.5f, 1.0f};
  clip.joint_tracks[1].rotation.values = {glm::quat(1.0002f, 0, 0, 0),
                                          axisAngleF(kPi / 4, {1, 0, 0}) * 3.0f,
                                          axisAngleF(kPi / 2, {1, 0, 0}) * 0.25f};
  c.clips.push_back(clip);
  EXPECT_LE(bakeAndCheck(c, fixedRate(30)), kSmoothMotionBound);
}

TEST(HardCases, CubicSplineWithLargeTangents) {
  Character c = chainCharacter(3);
  Clip clip = blankClip(c, "cubic", 1.0f);
  Vec3Track& t = clip.joint_tracks[1].translation;
  t.interpolation = Interpolation::kCubicSpline;
  t.times_seconds = {0.0f, 0.5f, 1.0f};
  const glm::vec3 big(50, 0, 0);  // Overshoots far beyond the key values.
  t.values = {big, glm::vec3(0, 1, 0), big, -big, glm::vec3(0, 1, 0), -big,
              big, glm::vec3(0, 1, 0), big};
  c.clips.push_back(clip);
  BakeReport r;
  EXPECT_LE(bakeAndCheck(c, fixedRate(60), &r), kLargeTangentBound);
  // The overshoot is real motion: the error is measured against it, and grows at 15 Hz.
  BakeReport low;
  bakeAndCheck(c, fixedRate(15), &low);
  EXPECT_GT(low.max_error_units, r.max_error_units);
}

TEST(HardCases, StepChannelsStaySteps) {
  Character c = chainCharacter(2);
  Clip clip = blankClip(c, "step", 1.0f);
  Vec3Track& t = clip.joint_tracks[1].translation;
  t.interpolation = Interpolation::kStep;
  // 0.35 s and 0.7 s fall inside 30 Hz frame intervals; 1.0 s is the clip's end.
  t.times_seconds = {0.0f, 0.35f, 0.7f, 1.0f};
  t.values = {{0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {3, 1, 0}};
  c.clips.push_back(clip);
  BakedPalette p;
  EXPECT_LE(bakeAndCheck(c, fixedRate(30), nullptr, &p), kExactBound);
  const BakedClip& bc = p.clips[0];
  const auto joint1_x = [&](double time) {
    std::vector<glm::mat4> mats(2);
    EXPECT_TRUE(emulateSkinningMatrices(p, 0, sampleFrames(bc, time), mats).isOk());
    return mats[1][3].x;  // Joint 1's translation x (its bind offset is along y only).
  };
  EXPECT_EQ(joint1_x(0.3499), 0.0f);
  EXPECT_EQ(joint1_x(0.35), 1.0f);  // At the key: the new value, no blend.
  EXPECT_EQ(joint1_x(0.36), 1.0f);
  EXPECT_EQ(joint1_x(0.6999), 1.0f);
  EXPECT_EQ(joint1_x(0.7), 2.0f);
  EXPECT_EQ(joint1_x(0.9999), 2.0f);
  EXPECT_EQ(joint1_x(1.0), 3.0f);   // A key on the end jumps only at the end.
}

TEST(HardCases, ChannelWithOneKey) {
  Character c = chainCharacter(2);
  Clip clip = blankClip(c, "one_key", 1.0f);
  clip.joint_tracks[1].rotation.times_seconds = {0.4f};
  clip.joint_tracks[1].rotation.values = {axisAngleF(0.7, {0, 0, 1})};
  c.clips.push_back(clip);
  EXPECT_LE(bakeAndCheck(c, fixedRate(30)), kExactBound);
}

TEST(HardCases, ZeroLengthClip) {
  Character c = chainCharacter(2);
  Clip clip = blankClip(c, "pose", 0.0f, LoopMode::kLoop);
  clip.joint_tracks[1].rotation.times_seconds = {0.0f};
  clip.joint_tracks[1].rotation.values = {axisAngleF(1.0, {1, 0, 0})};
  c.clips.push_back(clip);
  BakedPalette p;
  EXPECT_LE(bakeAndCheck(c, fixedRate(30), nullptr, &p), kExactBound);
  EXPECT_EQ(p.clips[0].frame_count, 1u);
  const FrameSample s = sampleFrames(p.clips[0], 123.0);
  EXPECT_EQ(s.frame, 0u);
  EXPECT_EQ(s.next_frame, 0u);
}

TEST(HardCases, SamplingExactlyAtTheClipEnd) {
  Character c = chainCharacter(2);
  Clip clip = blankClip(c, "end", 0.95f);  // Not a multiple of 1/30.
  clip.joint_tracks[1].translation.times_seconds = {0.0f, 0.95f};
  clip.joint_tracks[1].translation.values = {{0, 1, 0}, {5, 1, 0}};
  c.clips.push_back(clip);
  BakedPalette p;
  bakeAndCheck(c, fixedRate(30), nullptr, &p);
  const BakedClip& bc = p.clips[0];
  const FrameSample s = sampleFrames(bc, 0.95);
  EXPECT_EQ(s.next_frame, bc.frame_count - 1);
  EXPECT_EQ(s.fraction, 1.0f);
  std::vector<glm::mat4> mats(2);
  ASSERT_TRUE(emulateSkinningMatrices(p, 0, s, mats).isOk());
  EXPECT_EQ(mats[1][3].x, 5.0f);  // Ends exactly on the last key.
}

TEST(HardCases, LoopHoldsItsLastKeyUnlessItAsksToWrap) {
  Character c = chainCharacter(2);
  Clip clip = blankClip(c, "loop", 1.0f, LoopMode::kLoop);
  clip.joint_tracks[1].translation.times_seconds = {0.0f, 0.5f};
  clip.joint_tracks[1].translation.values = {{0, 1, 0}, {2, 1, 0}};
  c.clips.push_back(clip);
  clip.name = "wrap";
  clip.wrap_interpolates = true;
  c.clips.push_back(clip);
  BakedPalette p;
  EXPECT_LE(bakeAndCheck(c, fixedRate(30), nullptr, &p), kExactBound);
  std::vector<glm::mat4> mats(2);
  ASSERT_TRUE(emulateSkinningMatrices(p, 0, sampleFrames(p.clips[0], 0.75), mats).isOk());
  EXPECT_NEAR(mats[1][3].x, 2.0f, 1e-6f);  // Holds the last key.
  ASSERT_TRUE(emulateSkinningMatrices(p, 1, sampleFrames(p.clips[1], 0.75), mats).isOk());
  EXPECT_NEAR(mats[1][3].x, 1.0f, 1e-6f);  // Half way back to the first key.
}

Character scaledCharacter(glm::vec3 scale) {
  Character c = chainCharacter(3);
  Clip clip = blankClip(c, "scale", 1.0f);
  clip.joint_tracks[1].scale.times_seconds = {0.0f, 1.0f};
  clip.joint_tracks[1].scale.values = {glm::vec3(1.0f), scale};
  c.clips.push_back(clip);
  return c;
}

TEST(HardCases, ZeroTinyAndNegativeScale) {
  for (glm::vec3 scale : {glm::vec3(0.0f), glm::vec3(1e-7f), glm::vec3(-1.0f, 1.0f, 1.0f)}) {
    const Character c = scaledCharacter(scale);
    // Matrix formats represent any scale: the only error is the chord of the scale ramp.
    EXPECT_LE(bakeAndCheck(c, fixedRate(30)), kExactBound) << scale.x;
  }
  // The rigid format takes zero and tiny uniform scale but refuses a mirror, naming the joint.
  EXPECT_LE(bakeAndCheck(scaledCharacter(glm::vec3(0.0f)),
                         fixedRate(30, PaletteFormat::kQuatTranslationF32)),
            kExactBound);
  BakedPalette p;
  const Status s = bakePalette(scaledCharacter(glm::vec3(-1.0f, 1.0f, 1.0f)),
                               fixedRate(30, PaletteFormat::kQuatTranslationF32), &p, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kUnsupported);
  EXPECT_NE(s.message().find("clip 'scale'"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("'joint1'"), std::string::npos) << s.message();
}

TEST(HardCases, NonUniformScaleKeepsNormalsCorrect) {
  Character c = scaledCharacter(glm::vec3(3.0f, 1.0f, 0.5f));
  c.mesh.normals[4] = glm::normalize(glm::vec3(1, 0, 1));  // Off-axis, so scale bends it.
  BakedPalette p;
  EXPECT_LE(bakeAndCheck(c, fixedRate(30), nullptr, &p), kExactBound);
  EXPECT_EQ(bakePalette(c, fixedRate(30, PaletteFormat::kQuatTranslationF32), &p, nullptr).code(),
            StatusCode::kUnsupported);
  ASSERT_TRUE(bakePalette(c, fixedRate(30), &p, nullptr).isOk());
  // Emulated normals (cofactor) against the reference's inverse transpose at the end.
  std::vector<glm::mat4> mats(3);
  ASSERT_TRUE(emulateSkinningMatrices(p, 0, sampleFrames(p.clips[0], 1.0), mats).isOk());
  std::vector<glm::vec3> pos(c.mesh.vertexCount()), nrm(c.mesh.vertexCount());
  ASSERT_TRUE(emulateSkinning(c.mesh, mats, pos, nrm).isOk());
  ReferencePose pose;
  ASSERT_TRUE(evaluateLocalPose(c.skeleton, c.clips[0], 1.0, &pose).isOk());
  std::vector<glm::dvec3> rp(pos.size()), rn(pos.size());
  ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, rp, rn, {}).isOk());
  for (size_t v = 0; v < pos.size(); ++v)
    EXPECT_NEAR(glm::length(glm::dvec3(nrm[v]) - rn[v]), 0.0, 1e-6) << "vertex " << v;
  // And they are not what the plain matrix would give: the test can tell the difference.
  const glm::vec3 naive = glm::normalize(glm::mat3(mats[1]) * c.mesh.normals[4]);
  EXPECT_GT(glm::length(glm::dvec3(naive) - rn[4]), 0.1);
}

TEST(HardCases, WeightsSummingTo098AreRenormalizedAndZeroRejected) {
  Character c = chainCharacter(2);
  c.clips.push_back(blankClip(c, "still", 1.0f));
  c.mesh.weights[0] = glm::vec4(0.98f, 0, 0, 0);
  BakedPalette p;
  // Documented: the baker requires valid weights; normalizeWeights() repairs 0.98.
  EXPECT_EQ(bakePalette(c, fixedRate(30), &p, nullptr).code(), StatusCode::kInvalidArgument);
  WeightNormalizationReport r;
  ASSERT_TRUE(normalizeWeights(c.mesh, &r).isOk());
  EXPECT_NEAR(r.max_correction, 0.02f, 1e-6f);
  EXPECT_LE(bakeAndCheck(c, fixedRate(30)), kExactBound);
  c.mesh.weights[0] = glm::vec4(0.0f);
  EXPECT_EQ(normalizeWeights(c.mesh, nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(bakePalette(c, fixedRate(30), &p, nullptr).code(), StatusCode::kInvalidArgument);
}

// A weight too small for the vertex format (unorm16: below 1 / 131070 it stores 0) changes
// which vertices bound each joint's lever arm on the stored mesh. The automatic rate search must
// measure the same vertices on the reference and on the stored mesh: the rates it picks are
// those of the same character without the tiny weights (the mesh moves by < 1e-5 of a unit).
TEST(HardCases, TinyWeightsDoNotChangeTheRateSearchsVertices) {
  Character plain = chainCharacter(4);  // Rings 0..4 bound to joints 0, 1, 2, 3, 3.
  Clip clip = blankClip(plain, "bend", 1.0f, LoopMode::kLoop);
  QuatTrack& r = clip.joint_tracks[1].rotation;
  for (int k = 0; k <= 32; ++k) {  // 90 deg/s about Z, finely keyed.
    const double t = k / 32.0;
    r.times_seconds.push_back(float(t));
    r.values.push_back(axisAngleF(0.5 * kPi * std::sin(2.0 * kPi * t), {0, 0, 1}));
  }
  plain.clips.push_back(clip);
  // Rings 1 to 4 also lean on joint 0 by 5e-6: the reference's farthest vertices of joint 0
  // are then rings 3 and 4, the stored mesh's ring 0.
  Character tiny = plain;
  for (size_t v = 4; v < tiny.mesh.vertexCount(); ++v) {
    tiny.mesh.joints[v][1] = 0;
    tiny.mesh.weights[v] = glm::vec4(1.0f - 5e-6f, 5e-6f, 0.0f, 0.0f);
  }
  BakeDesc automatic;  // The default: automatic rates.
  BakeReport with_plain, with_tiny;
  bakeAndCheck(plain, automatic, &with_plain);
  bakeAndCheck(tiny, automatic, &with_tiny);
  ASSERT_EQ(with_plain.clips.size(), 1u);
  ASSERT_EQ(with_tiny.clips.size(), 1u);
  std::printf("[ tiny     ] rate %.0f Hz (plain %.0f Hz)\n", with_tiny.clips[0].sample_rate_hz,
              with_plain.clips[0].sample_rate_hz);
  EXPECT_EQ(with_tiny.clips[0].sample_rate_hz, with_plain.clips[0].sample_rate_hz);
  EXPECT_NEAR(with_tiny.max_error_units, with_plain.max_error_units, 1e-4);
}

TEST(HardCases, MoreThanFourInfluencesKeepTheLargestFour) {
  Character c = chainCharacter(6);
  c.clips.push_back(blankClip(c, "still", 1.0f));
  const Influence six[] = {{0, 0.3f}, {1, 0.25f}, {2, 0.2f}, {3, 0.1f}, {4, 0.1f}, {5, 0.05f}};
  float dropped = 0.0f;
  ASSERT_TRUE(reduceInfluences(six, &c.mesh.joints[5], &c.mesh.weights[5], &dropped).isOk());
  EXPECT_NEAR(dropped, 0.15f, 1e-6f);
  EXPECT_EQ(c.mesh.joints[5], glm::u16vec4(0, 1, 2, 3));
  EXPECT_LE(bakeAndCheck(c, fixedRate(30)), kExactBound);
}

TEST(HardCases, ThousandJointsStayWithinTheTextureLimit) {
  Character c = chainCharacter(1024);
  Clip clip = blankClip(c, "bend", 1.0f);
  for (size_t j = 1; j < 1024; j += 64) {
    clip.joint_tracks[j].rotation.times_seconds = {0.0f, 1.0f};
    clip.joint_tracks[j].rotation.values = {glm::quat(1, 0, 0, 0), axisAngleF(0.05, {0, 0, 1})};
  }
  c.clips.push_back(clip);
  BakeDesc d = fixedRate(30);
  d.max_texture_size = 1024;
  BakedPalette p;
  ASSERT_TRUE(bakePalette(c, d, &p, nullptr).isOk());
  EXPECT_LE(p.layout.width, 1024u);
  EXPECT_LE(p.layout.height, 1024u);
  EXPECT_EQ(p.palette_joints.size(), 1024u);
  d.max_texture_size = 256;  // 31 frames x 1024 joints x 4 texels do not fit in 256 x 256.
  const Status s = bakePalette(c, d, &p, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("256x256"), std::string::npos) << s.message();
}

TEST(HardCases, TenMinuteClipAt60Fps) {
  Character c = chainCharacter(3);
  Clip clip = blankClip(c, "long", 600.0f, LoopMode::kLoop);
  QuatTrack& r = clip.joint_tracks[1].rotation;
  for (int k = 0; k <= 600; ++k) {  // One key a second, swinging +-0.5 rad.
    r.times_seconds.push_back(float(k));
    r.values.push_back(axisAngleF(0.5 * std::sin(k * 0.7), {1, 0, 0}));
  }
  c.clips.push_back(clip);
  BakedPalette p;
  BakeReport rep;
  EXPECT_LE(bakeAndCheck(c, fixedRate(60), &rep, &p), kLongClipBound);
  EXPECT_EQ(p.clips[0].frame_count, 36001u);
  // Late in the clip the frame chosen is still exact: 599.5 s sits on frame 35970.
  const FrameSample s = sampleFrames(p.clips[0], 599.5);
  EXPECT_EQ(s.frame, 35970u);
  EXPECT_EQ(s.fraction, 0.0f);
}

// A key at 3e38 s (a hostile file's) asks for some 10^40 frames: refused by name from the
// frame count, for cubic frames (corner breaks) and STEP keys alike, without listing the
// frames first (which ran for minutes and gigabytes before 2026-11-29: the hostile glTF seed
// hostile_times_huge.gltf).
TEST(HardCases, AClipPastTheFrameLimitIsRefusedWithoutListingItsFrames) {
  for (bool step : {false, true}) {
    SCOPED_TRACE(step);
    Character c = chainCharacter(2);
    Clip clip = blankClip(c, "forever", 3e38f);
    QuatTrack& r = clip.joint_tracks[1].rotation;
    r.interpolation = step ? Interpolation::kStep : Interpolation::kLinear;
    r.times_seconds = {0.0f, 0.5f, 3e38f};
    r.values = {axisAngleF(0.0, {1, 0, 0}), axisAngleF(0.4, {1, 0, 0}), axisAngleF(0.8, {1, 0, 0})};
    c.clips.push_back(clip);
    BakeDesc d = fixedRate(30);
    d.interpolation = InterpolationChoice::kCubic;  // Corner breaks for LINEAR keys.
    BakedPalette p;
    const Status s = bakePalette(c, d, &p, nullptr);
    EXPECT_EQ(s.code(), StatusCode::kLimitExceeded) << s.toString();
    EXPECT_NE(s.message().find("at most 2^20"), std::string::npos) << s.toString();
    const FramePlan plan = planClipFrames(c.clips[0], 30.0, true);
    EXPECT_GT(plan.frame_count, 1u << 20);
    EXPECT_TRUE(plan.frame_times_seconds.empty());
  }
}

TEST(HardCases, ErrorGrowsAsTheRateDropsAt720DegreesPerSecond) {
  Character c = chainCharacter(3);
  Clip clip = blankClip(c, "spin", 1.0f, LoopMode::kLoop);
  QuatTrack& r = clip.joint_tracks[0].rotation;
  for (int k = 0; k <= 64; ++k) {  // 720 deg/s about Z, finely keyed so the reference is smooth.
    const double t = k / 64.0;
    r.times_seconds.push_back(float(t));
    r.values.push_back(axisAngleF(4 * kPi * t, {0, 0, 1}));
  }
  c.clips.push_back(clip);
  double previous = 0.0;
  for (float hz : {60.0f, 30.0f, 15.0f}) {
    BakeReport rep;
    bakeAndCheck(c, fixedRate(hz), &rep);
    std::printf("[ 720 deg/s ] %4.0f Hz: max %.4g units (%.3g of height), P99 %.4g\n", hz,
                rep.max_error_units, rep.max_error_ratio, rep.p99_error_units);
    EXPECT_GT(rep.max_error_units, previous) << hz << " Hz";
    previous = rep.max_error_units;
  }
  // At 15 Hz (48 degrees a frame) a matrix lerp visibly shrinks the chain: the report says so.
  EXPECT_GT(previous / 3.0, 0.01);
}

}  // namespace
}  // namespace si
