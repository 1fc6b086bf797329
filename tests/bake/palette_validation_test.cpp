// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// BakedPalette::validate(): every bake passes it (every format, fixed and automatic rates, STEP
// frames, single-frame clips), and each rule broken on its own fails with its code; the sample
// function stays in range on palettes that fail it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "bake/bake_test_helpers.h"

namespace si {
namespace {

using test::smallPalette;

// Bakes of the embedded character (automatic f32; every format at 60 Hz with STEP clips) are
// validated in animation_baker_test.cpp, where they are made anyway.
TEST(PaletteValidation, EveryBakePasses) {
  for (PaletteFormat f : {PaletteFormat::kMatrix3x4F32, PaletteFormat::kMatrix3x4F16,
                          PaletteFormat::kQuatTranslationF32}) {
    const Status s = smallPalette(f).validate();  // STEP frame times and a loop.
    EXPECT_TRUE(s.isOk()) << paletteFormatName(f) << ": " << s.toString();
  }
  // Automatic rates, and a clip of one frame (duration 0).
  Character chain = test::chainCharacter(3);
  Clip swing = test::blankClip(chain, "swing", 0.7f, LoopMode::kLoop);
  swing.joint_tracks[2].rotation.times_seconds = {0.0f, 0.35f, 0.7f};
  swing.joint_tracks[2].rotation.values = {glm::quat(1, 0, 0, 0), test::axisAngleF(1.2, {1, 0, 0}),
                                           glm::quat(1, 0, 0, 0)};
  chain.clips.push_back(swing);
  chain.clips.push_back(test::blankClip(chain, "pose", 0.0f));
  BakeDesc d;
  d.rate_mode = RateMode::kAutomatic;
  BakedPalette p;
  ASSERT_TRUE(bakePalette(chain, d, &p, nullptr).isOk());
  ASSERT_GT(p.clips[0].frame_count, 10u);
  ASSERT_EQ(p.clips[1].frame_count, 1u);
  EXPECT_TRUE(p.validate().isOk()) << p.validate().toString();
}

// Found by fuzzing glTF import + bake (2026-11-23): a mesh spanning 1e22 units or more baked a
// palette that its own validation refused, because the half diagonal of the box was computed
// in float and overflowed. Huge finite meshes bake into palettes that validate, or are refused
// by name; a sphere too small for a huge box is still caught.
TEST(PaletteValidation, HugeMeshesBakeIntoValidPalettesOrAreRefused) {
  for (const double scale : {1e19, 1e22, 1e30, 1e36}) {
    SCOPED_TRACE(scale);
    Character chain = test::chainCharacter(3);
    Clip swing = test::blankClip(chain, "swing", 0.5f, LoopMode::kLoop);
    swing.joint_tracks[2].rotation.times_seconds = {0.0f, 0.5f};
    swing.joint_tracks[2].rotation.values = {glm::quat(1, 0, 0, 0), test::axisAngleF(1.0, {1, 0, 0})};
    chain.clips.push_back(swing);
    for (glm::vec3& p : chain.mesh.positions) p = glm::vec3(glm::dvec3(p) * scale);
    for (glm::mat4& m : chain.skeleton.inverse_bind_matrices)
      m[3] = glm::vec4(glm::vec3(glm::dvec3(m[3]) * scale), 1.0f);
    for (Transform& t : chain.skeleton.rest_pose) t.translation = glm::vec3(glm::dvec3(t.translation) * scale);
    for (Clip& c : chain.clips)
      for (JointTracks& j : c.joint_tracks)
        for (glm::vec3& v : j.translation.values) v = glm::vec3(glm::dvec3(v) * scale);
    BakeDesc d;
    d.rate_mode = RateMode::kFixed;
    BakedPalette p;
    const Status s = bakePalette(chain, d, &p, nullptr);
    if (s.isOk()) {
      EXPECT_TRUE(p.validate().isOk()) << p.validate().toString();
    } else {
      EXPECT_FALSE(s.message().empty());
    }
    if (scale <= 1e22) {
      EXPECT_TRUE(s.isOk()) << s.toString();
    }
  }
  BakedPalette p = smallPalette(PaletteFormat::kMatrix3x4F32);
  p.clips[0].bounds.min = glm::vec3(-1e30f);
  p.clips[0].bounds.max = glm::vec3(1e30f);
  p.clips[0].bounding_sphere.center = glm::vec3(0.0f);
  p.clips[0].bounding_sphere.radius = 1.7321e30f;  // Half the diagonal, 1e30 x sqrt(3).
  EXPECT_TRUE(p.validate().isOk()) << p.validate().toString();
  p.clips[0].bounding_sphere.radius = 1.5e30f;
  EXPECT_EQ(p.validate().code(), StatusCode::kOutOfRange);
}

// Breaks one rule of a valid palette and expects its code.
void expectBroken(PaletteFormat format, StatusCode code, const char* what,
                  const std::function<void(BakedPalette&)>& breakIt) {
  BakedPalette p = smallPalette(format);
  ASSERT_TRUE(p.validate().isOk());
  breakIt(p);
  const Status s = p.validate();
  EXPECT_EQ(s.code(), code) << what << ": " << s.toString();
}

TEST(PaletteValidation, EachBrokenRuleHasItsCode) {
  const PaletteFormat f32 = PaletteFormat::kMatrix3x4F32;
  using C = StatusCode;
  expectBroken(f32, C::kInvalidArgument, "format", [](BakedPalette& p) {
    p.format = PaletteFormat::kDefault;
  });
  expectBroken(f32, C::kInvalidArgument, "no joints", [](BakedPalette& p) {
    p.palette_joints.clear();
  });
  expectBroken(f32, C::kInvalidArgument, "joint map", [](BakedPalette& p) {
    p.skeleton_to_palette[0] = 1;
  });
  expectBroken(f32, C::kInvalidArgument, "joints out of order", [](BakedPalette& p) {
    std::swap(p.palette_joints[0], p.palette_joints[1]);
  });
  expectBroken(f32, C::kInvalidArgument, "no clips", [](BakedPalette& p) { p.clips.clear(); });
  expectBroken(f32, C::kInvalidArgument, "layout", [](BakedPalette& p) { p.layout.width *= 2; });
  expectBroken(f32, C::kInvalidArgument, "first texel", [](BakedPalette& p) {
    p.clips[1].first_texel += 4;
  });
  expectBroken(f32, C::kInvalidArgument, "frame count vs layout", [](BakedPalette& p) {
    p.clips[1].frame_count += 1;
    p.clips[1].frame_interval_seconds = p.clips[1].duration_seconds / (p.clips[1].frame_count - 1);
  });
  expectBroken(f32, C::kCountMismatch, "texel bytes", [](BakedPalette& p) {
    p.texel_bytes.pop_back();
  });
  expectBroken(f32, C::kNotFinite, "texel", [](BakedPalette& p) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(p.texel_bytes.data() + 16 * 5, &nan, 4);
  });
  expectBroken(PaletteFormat::kMatrix3x4F16, C::kNotFinite, "half texel", [](BakedPalette& p) {
    const uint16_t inf = 0x7C00;
    std::memcpy(p.texel_bytes.data() + 8 * 5, &inf, 2);
  });
  expectBroken(PaletteFormat::kQuatTranslationF32, C::kOutOfRange, "non-unit quaternion",
               [](BakedPalette& p) {
                 const float two = 2.0f;
                 std::memcpy(p.texel_bytes.data(), &two, 4);
               });
  expectBroken(PaletteFormat::kQuatTranslationF32, C::kOutOfRange, "zero scale",
               [](BakedPalette& p) {
                 const float zero = 0.0f;
                 std::memcpy(p.texel_bytes.data() + 16 + 12, &zero, 4);
               });
  expectBroken(f32, C::kOutOfRange, "loop mode", [](BakedPalette& p) {
    p.clips[0].loop_mode = LoopMode::kDefault;
  });
  expectBroken(f32, C::kOutOfRange, "interval 1e-230", [](BakedPalette& p) {
    p.clips[1].frame_interval_seconds = 1e-230;
  });
  expectBroken(f32, C::kOutOfRange, "interval not dividing", [](BakedPalette& p) {
    p.clips[1].frame_interval_seconds *= 1.3;
  });
  expectBroken(f32, C::kOutOfRange, "duration", [](BakedPalette& p) {
    p.clips[1].duration_seconds = std::numeric_limits<float>::infinity();
  });
  expectBroken(f32, C::kOutOfRange, "single frame with interval", [](BakedPalette& p) {
    BakedClip& c = p.clips[1];
    c.frame_count = 1;
  });
  expectBroken(f32, C::kCountMismatch, "frame time count", [](BakedPalette& p) {
    p.clips[0].frame_times_seconds.pop_back();
  });
  expectBroken(f32, C::kOutOfRange, "frame times out of order", [](BakedPalette& p) {
    std::swap(p.clips[0].frame_times_seconds[1], p.clips[0].frame_times_seconds[2]);
  });
  expectBroken(f32, C::kOutOfRange, "frame time past the duration", [](BakedPalette& p) {
    p.clips[0].frame_times_seconds.back() += 1.0;
  });
  expectBroken(f32, C::kOutOfRange, "empty box", [](BakedPalette& p) {
    p.clips[0].bounds.max.x = p.clips[0].bounds.min.x - 1.0f;
  });
  expectBroken(f32, C::kOutOfRange, "sphere smaller than the box", [](BakedPalette& p) {
    p.clips[0].bounding_sphere.radius *= 0.5f;
  });
  expectBroken(f32, C::kOutOfRange, "character height", [](BakedPalette& p) {
    p.character_height = -1.0f;
  });
}

TEST(PaletteValidation, SampleFramesStaysInRangeOnAnyClip) {
  BakedPalette p = smallPalette();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (BakedClip clip : p.clips) {
    // The shapes the loader now refuses: an interval orders of magnitude off, frame times that
    // do not match the frame count, a huge duration.
    for (int variant = 0; variant < 4; ++variant) {
      BakedClip c = clip;
      if (variant == 1) c.frame_interval_seconds = 1e-230;
      if (variant == 2) c.frame_times_seconds.resize(c.frame_times_seconds.size() / 2);
      if (variant == 3) c.duration_seconds = 3e38f;
      for (double t : {0.0, 0.1, 1e300, -1e300, nan, inf, -inf}) {
        const FrameSample s = sampleFrames(c, t);
        EXPECT_LT(s.frame, c.frame_count);
        EXPECT_LT(s.next_frame, std::max(c.frame_count, 2u));
        EXPECT_TRUE(s.fraction >= 0.0f && s.fraction <= 1.0f) << "t " << t;
      }
    }
  }
}

}  // namespace
}  // namespace si
