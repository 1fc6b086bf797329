// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Cubic interpolation between baked frames: the emulation against the reference at and between
// frames, seamless loops, clip ends, STEP holds, corner keys, the automatic rate and the
// palette rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "bake/bake_test_helpers.h"
#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {

using test::axisAngleF;
using test::blankClip;
using test::chainCharacter;

const Character& embedded() {
  static const Character c = [] {
    Character ch;
    EXPECT_TRUE(makeDefaultCharacter({}, &ch).isOk());
    return ch;
  }();
  return c;
}

BakedPalette bakeCubic(const Character& c, float rate, PaletteFormat format,
                       BakeReport* report = nullptr) {
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = rate;
  d.format = format;
  d.interpolation = InterpolationChoice::kCubic;
  BakedPalette p;
  const Status s = bakePalette(c, d, &p, report);
  EXPECT_TRUE(s.isOk()) << s.toString();
  return p;
}

// Largest vertex distance between the emulated cubic palette and the reference at time t.
double errorAt(const Character& c, const BakedPalette& p, uint32_t clip, double t) {
  std::vector<glm::mat4> mats(c.skeleton.jointCount());
  EXPECT_TRUE(emulateSkinningMatrices(p, clip, sampleFrames(p.clips[clip], t), mats).isOk());
  std::vector<glm::vec3> emulated(c.mesh.vertexCount());
  SkinnedMesh gpu_mesh = c.mesh;
  for (glm::vec4& w : gpu_mesh.weights) w = dequantizeWeights(quantizeWeights(w));
  EXPECT_TRUE(emulateSkinning(gpu_mesh, mats, emulated, {}).isOk());
  ReferencePose pose;
  const Clip& source = c.clips[size_t(c.findClip(p.clips[clip].name))];
  EXPECT_TRUE(evaluateLocalPose(c.skeleton, source, t, &pose).isOk());
  std::vector<glm::dvec3> ref(c.mesh.vertexCount());
  EXPECT_TRUE(skinVertices(c.mesh, pose.skinning, ref, {}, {}).isOk());
  double worst = 0.0;
  for (size_t v = 0; v < ref.size(); ++v)
    worst = std::max(worst, glm::length(glm::dvec3(emulated[v]) - ref[v]));
  return worst;
}

TEST(CubicInterpolation, FractionWordsCarryTheModeAndKeepTheFraction) {
  for (IntervalMode m : {IntervalMode::kLinear, IntervalMode::kCubic,
                         IntervalMode::kCubicStartsHere, IntervalMode::kCubicEndsNext})
    for (float f : {0.0f, 1e-30f, 0.25f, 0.7f, std::nextafter(1.0f, 0.0f), 1.0f}) {
      IntervalMode back;
      EXPECT_EQ(unpackFraction(packFraction(f, m), &back), f);
      EXPECT_EQ(back, m);
    }
  // A linear word is the fraction's own bits, as records were before modes existed.
  const float half = 0.5f;
  uint32_t bits;
  std::memcpy(&bits, &half, 4);
  EXPECT_EQ(packFraction(half, IntervalMode::kLinear), bits);
}

// At a frame's time the spline passes through the baked frame exactly; between frames the
// error stays within what the bake reports (plus a quarter: the report samples each interval
// at four fractions, the check at random ones).
TEST(CubicInterpolation, EmulationHitsFramesExactlyAndStaysWithinTheReportBetween) {
  for (PaletteFormat format : {PaletteFormat::kMatrix3x4F32, PaletteFormat::kQuatTranslationF32}) {
    BakeReport report;
    const BakedPalette p = bakeCubic(embedded(), 60.0f, format, &report);
    ASSERT_EQ(p.layout.border_frames, 1u);
    std::mt19937 rng(7);
    for (uint32_t c = 0; c < p.clips.size(); ++c) {
      const BakedClip& clip = p.clips[c];
      ASSERT_EQ(clip.interpolation, FrameInterpolation::kCubic);
      ASSERT_EQ(clip.interval_modes.size(), clip.frame_count - 1u);
      for (uint32_t f = 0; f < clip.frame_count; f += 7) {
        FrameSample s;
        s.frame = f;
        s.next_frame = std::min(f + 1, clip.frame_count - 1);
        s.mode = intervalModeAt(clip, std::min(f, clip.frame_count - 2));
        for (uint32_t slot = 0; slot < p.palette_joints.size(); ++slot) {
          const glm::mat4 m = emulateSkinningMatrix(p, c, s, slot), frame = decodeJoint(p, c, f, slot);
          if (format == PaletteFormat::kQuatTranslationF32) {  // Renormalized: within rounding.
            for (int col = 0; col < 4; ++col)
              for (int row = 0; row < 3; ++row) ASSERT_NEAR(m[col][row], frame[col][row], 1e-6);
          } else {
            ASSERT_EQ(m, frame) << clip.name << " frame " << f << " slot " << slot;
          }
        }
      }
      std::uniform_real_distribution<double> time(0.0, clip.duration_seconds);
      double worst = 0.0;
      for (int k = 0; k < 40; ++k) worst = std::max(worst, errorAt(embedded(), p, c, time(rng)));
      EXPECT_LE(worst, 1.25 * report.clips[c].max_error_units + 1e-6)
          << paletteFormatName(format) << " " << clip.name;
      EXPECT_GT(report.clips[c].max_error_units, 0.0);
    }
  }
}

// The embedded run clip loops a smooth (cubic-spline) gait: its border frames continue the
// loop, its first and last intervals are full cubics, and the error at the wrap is no larger
// than elsewhere.
TEST(CubicInterpolation, LoopsAreSeamlessAtTheWrap) {
  const BakedPalette p = bakeCubic(embedded(), 30.0f, PaletteFormat::kMatrix3x4F32);
  const uint32_t c = uint32_t(p.findClip("run"));
  const BakedClip& clip = p.clips[c];
  ASSERT_EQ(clip.loop_mode, LoopMode::kLoop);
  const uint32_t n = clip.frame_count;
  EXPECT_EQ(intervalModeAt(clip, 0), IntervalMode::kCubic);
  EXPECT_EQ(intervalModeAt(clip, n - 2), IntervalMode::kCubic);
  const uint32_t stride = p.layout.frame_stride_texels;
  for (uint32_t slot = 0; slot < p.palette_joints.size(); ++slot) {
    const glm::mat4 before = emulateFrameMatrix(p, clip.first_texel - stride,
                                                clip.first_texel - stride, 0.0f, slot);
    const glm::mat4 after = emulateFrameMatrix(p, clip.first_texel + n * stride,
                                               clip.first_texel + n * stride, 0.0f, slot);
    EXPECT_EQ(before, decodeJoint(p, c, n - 2, slot));
    EXPECT_EQ(after, decodeJoint(p, c, 1, slot));
  }
  const double dt = clip.frame_interval_seconds;
  double wrap = 0.0, inside = 0.0;
  for (int k = 1; k < 8; ++k) {
    const double u = k / 8.0;
    wrap = std::max({wrap, errorAt(embedded(), p, c, u * dt),
                     errorAt(embedded(), p, c, clip.duration_seconds - u * dt)});
    for (uint32_t i = 1; i + 2 < n; ++i)
      inside = std::max(inside, errorAt(embedded(), p, c, (i + u) * dt));
  }
  EXPECT_GT(inside, 0.0);
  // The gait repeats within the period, so the wrap's intervals mirror inner ones: equal up to
  // float rounding (measured 8.34211e-4 vs 8.34199e-4 at 30 Hz).
  EXPECT_LE(wrap, inside * (1.0 + 1e-4)) << "wrap " << wrap << " inside " << inside;
}

// A clip played once extrapolates from its own frames at its ends (no loop to continue) and
// ends exactly on its last frame, which holds the reference pose at the end.
TEST(CubicInterpolation, OnceClipsStartAndEndOnTheirOwnFrames) {
  Character c = chainCharacter(3);
  Clip bend = blankClip(c, "bend", 1.0f);
  bend.joint_tracks[1].rotation.interpolation = Interpolation::kCubicSpline;
  for (int k = 0; k <= 4; ++k) {
    const float t = 0.25f * float(k);
    bend.joint_tracks[1].rotation.times_seconds.push_back(t);
    const glm::quat q = axisAngleF(1.2 * std::sin(2.0 * t), {0, 0, 1});
    bend.joint_tracks[1].rotation.values.insert(bend.joint_tracks[1].rotation.values.end(),
                                                {glm::quat(0, 0, 0, 0), q, glm::quat(0, 0, 0, 0)});
  }
  c.clips.push_back(bend);
  const BakedPalette p = bakeCubic(c, 20.0f, PaletteFormat::kMatrix3x4F32);
  const BakedClip& clip = p.clips[0];
  const uint32_t n = clip.frame_count;
  EXPECT_EQ(intervalModeAt(clip, 0), IntervalMode::kCubicStartsHere);
  EXPECT_EQ(intervalModeAt(clip, n - 2), IntervalMode::kCubicEndsNext);
  for (uint32_t i = 1; i + 2 < n; ++i) EXPECT_EQ(intervalModeAt(clip, i), IntervalMode::kCubic);
  const FrameSample end = sampleFrames(clip, 5.0);  // Past the end: clamped.
  EXPECT_EQ(end.next_frame, n - 1);
  EXPECT_EQ(end.fraction, 1.0f);
  ReferencePose pose;
  ASSERT_TRUE(evaluateLocalPose(c.skeleton, bend, 1.0, &pose).isOk());
  for (uint32_t slot = 0; slot < p.palette_joints.size(); ++slot) {
    const glm::mat4 m = emulateSkinningMatrix(p, 0, end, slot);
    EXPECT_EQ(m, decodeJoint(p, 0, n - 1, slot));
    const glm::dmat4& ref = pose.skinning[p.palette_joints[slot]];
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 3; ++row) EXPECT_NEAR(m[col][row], ref[col][row], 1e-6);
  }
  // The ends are as accurate as the middle: extrapolating from three frames of one side.
  const double dt = clip.frame_interval_seconds;
  const double first = errorAt(c, p, 0, 0.5 * dt), last = errorAt(c, p, 0, 1.0 - 0.5 * dt);
  double middle = 0.0;
  for (uint32_t i = 1; i + 2 < n; ++i) middle = std::max(middle, errorAt(c, p, 0, (i + 0.5) * dt));
  EXPECT_LE(std::max(first, last), 4.0 * middle + 1e-6);
}

// smallPalette's "step" clip holds joint 1's translation and jumps at 0.25 s: before and after
// the jump every time plays the held value (no cubic overshoot towards the other side).
TEST(CubicInterpolation, StepHoldsNeverBlend) {
  const BakedPalette p = test::smallPalette(PaletteFormat::kMatrix3x4F32,
                                            InterpolationChoice::kCubic);
  const uint32_t c = uint32_t(p.findClip("step"));
  const BakedClip& clip = p.clips[c];
  ASSERT_FALSE(clip.frame_times_seconds.empty());
  const uint32_t slot = uint32_t(p.skeleton_to_palette[1]);
  const glm::mat4 held_before = decodeJoint(p, c, 0, slot);
  const glm::mat4 held_after = decodeJoint(p, c, clip.frame_count - 1, slot);
  ASSERT_NE(held_before[3], held_after[3]);
  bool saw_pair = false;
  for (uint32_t i = 0; i + 1 < clip.frame_count; ++i)
    if (clip.frame_times_seconds[i] == clip.frame_times_seconds[i + 1]) {
      saw_pair = true;
      EXPECT_EQ(intervalModeAt(clip, i), IntervalMode::kLinear);
      // The neighbours never read across the pair (linear, or extrapolating from their side).
      if (i > 0) {
        const IntervalMode m = intervalModeAt(clip, i - 1);
        EXPECT_TRUE(m == IntervalMode::kLinear || m == IntervalMode::kCubicEndsNext);
      }
      if (i + 2 < clip.frame_count) {
        const IntervalMode m = intervalModeAt(clip, i + 1);
        EXPECT_TRUE(m == IntervalMode::kLinear || m == IntervalMode::kCubicStartsHere);
      }
    }
  EXPECT_TRUE(saw_pair);
  for (int k = 0; k < 200; ++k) {
    const double t = 0.5 * k / 200.0;
    const glm::mat4 m = emulateSkinningMatrix(p, c, sampleFrames(clip, t), slot);
    const glm::mat4& held = t < 0.25 ? held_before : held_after;
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 3; ++row)
        ASSERT_NEAR(m[col][row], held[col][row], 1e-6) << "t=" << t;
  }
}

// Keys of LINEAR tracks are corners: a cubic plan puts a frame on each (marking the grid frame
// when one is within 1e-3 intervals, adding one otherwise) and breaks the spline there.
TEST(CubicInterpolation, CornerKeysGetFramesAndBreaks) {
  Character c = chainCharacter(2);
  Clip clip = blankClip(c, "keys", 1.0f);
  clip.joint_tracks[1].rotation.times_seconds = {0.0f, 0.25f, 0.6f, 1.0f};
  clip.joint_tracks[1].rotation.values = {glm::quat(1, 0, 0, 0), axisAngleF(0.4, {1, 0, 0}),
                                          axisAngleF(-0.3, {1, 0, 0}), glm::quat(1, 0, 0, 0)};
  EXPECT_EQ(cornerKeyTimes(clip), (std::vector<double>{0.25, double(0.6f)}));
  EXPECT_EQ(cornerKeyRate(clip), 0.0);  // 0.6 is not a multiple of 0.25 (nor 1.0 of 0.35).
  const FramePlan linear = planClipFrames(clip, 20.0);
  EXPECT_EQ(linear.frame_count, 21u);
  EXPECT_TRUE(linear.breaks.empty());
  const FramePlan cubic = planClipFrames(clip, 20.0, true);
  // 0.25 lies on the 20 Hz grid (frame 5): marked. 0.6f lies 1.2e-8 s off frame 12: marked.
  EXPECT_EQ(cubic.frame_count, 21u);
  ASSERT_EQ(cubic.breaks.size(), 21u);
  for (uint32_t f = 0; f < 21; ++f)
    EXPECT_EQ(cubic.breaks[f], f == 0 || f == 5 || f == 12 || f == 20 ? 1 : 0) << f;
  const FramePlan off = planClipFrames(clip, 16.0, true);  // 0.25 on the grid, 0.6 not.
  EXPECT_EQ(off.frame_count, 18u);
  ASSERT_EQ(off.frame_times_seconds.size(), 18u);
  EXPECT_EQ(off.frame_times_seconds[10], double(0.6f));
  EXPECT_EQ(off.breaks[10], 1);
  EXPECT_EQ(off.breaks[4], 1);  // 0.25 = 4 / 16.
  // Keys sampled at 24 Hz: the corner grid's rate.
  Clip sampled = blankClip(c, "sampled", 2.0f);
  for (int k = 0; k <= 48; ++k) {
    sampled.joint_tracks[1].rotation.times_seconds.push_back(float(k / 24.0));
    sampled.joint_tracks[1].rotation.values.push_back(axisAngleF(0.1 * k, {1, 0, 0}));
  }
  EXPECT_NEAR(cornerKeyRate(sampled), 24.0, 1e-9);
}

// The automatic rate: on smooth clips cubic needs far fewer frames than linear at the same
// tolerance; kSmaller takes the smaller of the two per clip; every clip meets the tolerance.
TEST(CubicInterpolation, AutomaticRatesNeedFewerFramesAndSmallerPicksPerClip) {
  BakeReport linear, cubic, smaller;
  BakedPalette p;
  BakeDesc d;
  d.clip_names = {"walk", "run"};  // Corner keys at 24 Hz, and a smooth spline.
  ASSERT_TRUE(bakePalette(embedded(), d, &p, &linear).isOk());
  d.interpolation = InterpolationChoice::kCubic;
  ASSERT_TRUE(bakePalette(embedded(), d, &p, &cubic).isOk());
  d.interpolation = InterpolationChoice::kSmaller;
  ASSERT_TRUE(bakePalette(embedded(), d, &p, &smaller).isOk());
  ASSERT_EQ(linear.clips.size(), cubic.clips.size());
  for (size_t c = 0; c < linear.clips.size(); ++c) {
    EXPECT_TRUE(linear.clips[c].tolerance_met);
    EXPECT_TRUE(cubic.clips[c].tolerance_met) << cubic.clips[c].name;
    EXPECT_TRUE(smaller.clips[c].tolerance_met);
    // Both meet the tolerance here: the one with fewer frames (the smaller error on a tie).
    const bool cubic_wins = cubic.clips[c].frame_count != linear.clips[c].frame_count
                                ? cubic.clips[c].frame_count < linear.clips[c].frame_count
                                : cubic.clips[c].max_error_units < linear.clips[c].max_error_units;
    EXPECT_EQ(smaller.clips[c].frame_count,
              std::min(linear.clips[c].frame_count, cubic.clips[c].frame_count));
    EXPECT_EQ(smaller.clips[c].interpolation,
              cubic_wins ? FrameInterpolation::kCubic : FrameInterpolation::kLinear);
  }
  const auto frames = [](const BakeReport& r, const char* name) {
    for (const ClipErrorReport& e : r.clips)
      if (e.name == name) return e.frame_count;
    return 0u;
  };
  // run is a cubic-spline gait (smooth), walk slerps keys sampled at 24 Hz (corners).
  EXPECT_LT(2 * frames(cubic, "run"), frames(linear, "run"));
  EXPECT_LT(cubic.palette_bytes, linear.palette_bytes);
}

TEST(CubicInterpolation, PalettesWithBrokenInterpolationFieldsAreRefused) {
  const BakedPalette good = test::smallPalette(PaletteFormat::kMatrix3x4F32,
                                               InterpolationChoice::kCubic);
  ASSERT_TRUE(good.validate().isOk());
  BakedPalette p = good;
  p.clips[1].interval_modes.pop_back();
  EXPECT_EQ(p.validate().code(), StatusCode::kCountMismatch);
  p = good;
  p.clips[1].interval_modes[0] = 4;
  EXPECT_EQ(p.validate().code(), StatusCode::kOutOfRange);
  p = good;
  p.clips[1].interpolation = static_cast<FrameInterpolation>(9);
  EXPECT_EQ(p.validate().code(), StatusCode::kInvalidArgument);
  p = good;
  p.clips[1].interpolation = FrameInterpolation::kLinear;  // Modes on a linear clip.
  EXPECT_EQ(p.validate().code(), StatusCode::kInvalidArgument);
  // A cubic clip in a palette without border frames.
  BakedPalette linear = test::smallPalette();
  linear.clips[1].interpolation = FrameInterpolation::kCubic;
  linear.clips[1].interval_modes.assign(linear.clips[1].frame_count - 1, 1);
  EXPECT_EQ(linear.validate().code(), StatusCode::kInvalidArgument);
  // A border frame that is not finite.
  p = good;
  const uint32_t texel = p.clips[0].first_texel - p.layout.frame_stride_texels;
  const float nan = std::nanf("");
  std::memcpy(p.texel_bytes.data() + size_t(texel) * 16, &nan, 4);
  EXPECT_EQ(p.validate().code(), StatusCode::kNotFinite);
}

}  // namespace
}  // namespace si
