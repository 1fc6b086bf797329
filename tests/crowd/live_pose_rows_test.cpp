// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The live poses' one pass (crowd/live_pose_rows.h: check, rows and box), in every variant this
// CPU runs (SSE2, F16C), against the one-value-at-a-time references, on the values where a half
// float's rounding is hard.
#include "crowd/live_pose_rows.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

namespace si::detail {
namespace {

float fromBits(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

// Identity-last-row matrices whose first three rows hold `values` (12 a matrix; the last one
// padded with 1).
std::vector<glm::mat4> matricesOf(const std::vector<float>& values) {
  std::vector<glm::mat4> out((values.size() + 11) / 12, glm::mat4(1.0f));
  for (size_t k = 0; k < values.size(); ++k) out[k / 12][int(k % 12 / 3)][int(k % 3)] = values[k];
  return out;
}

// Every magnitude a half float holds or rounds to (0 to 65504) at a prime stride of float bit
// patterns, with the hard ones exactly: rounding ties between halves (normal and subnormal),
// where subnormals round up to the smallest normal, float subnormals, the largest half; each
// with both signs.
std::vector<float> hardValues() {
  std::vector<float> v;
  for (uint32_t u = 0; u <= 0x477FE000u; u += 4099u) v.push_back(fromBits(u));
  const float tie = std::ldexp(1.0f, -11);  // Half of a half's step at 1.
  for (float x :
       {1.0f + tie, 1.0f + 3.0f * tie, 2.0f - tie, 65504.0f, 65503.0f, 1024.5f,
        std::ldexp(1.0f, -25), std::ldexp(3.0f, -25), std::ldexp(5.0f, -25),
        std::ldexp(1.0f, -14) - std::ldexp(1.0f, -25),
        std::ldexp(1.0f, -14) - std::ldexp(1.0f, -26), std::ldexp(1.0f, -14), std::ldexp(1.0f, -24),
        std::ldexp(1.0f, -26), std::ldexp(1.0f, -149), std::ldexp(1.0f, -126), 0.0f})
    v.push_back(x);
  for (uint32_t m = 0; m < 4096; ++m)  // Ties and their neighbours around 1.
    v.push_back(fromBits(0x3F800000u + m * 0x1000u + (m % 3) - 1u));
  const size_t n = v.size();
  for (size_t k = 0; k < n; ++k) v.push_back(-v[k]);
  return v;
}

// The variants this build and CPU run, each named.
std::vector<std::pair<PoseRowsIsa, const char*>> variants() {
  std::vector<std::pair<PoseRowsIsa, const char*>> out;
  for (auto v :
       {std::make_pair(PoseRowsIsa::kReference, "reference"),
        std::make_pair(PoseRowsIsa::kSse2, "SSE2"), std::make_pair(PoseRowsIsa::kF16c, "F16C"),
        std::make_pair(PoseRowsIsa::kBest, "best")})
    if (runs(v.first)) out.push_back(v);
  return out;
}

// x86-64 builds hold the four-at-a-time variant, and F16C runs on every CPU of the machines
// the tests run on (the VM and CI's); elsewhere the tests say so.
TEST(LivePoseRows, TheFastVariantsRunHere) {
#if defined(__x86_64__)
  EXPECT_TRUE(runs(PoseRowsIsa::kSse2));
#endif
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)  // Clang has no "f16c" here.
  __builtin_cpu_init();
  EXPECT_EQ(runs(PoseRowsIsa::kF16c),
            __builtin_cpu_supports("avx") != 0 && __builtin_cpu_supports("f16c") != 0);
  if (!runs(PoseRowsIsa::kF16c)) GTEST_SKIP() << "this CPU has no F16C: only SSE2 is tested";
#endif
}

TEST(LivePoseRows, RowsAreStoredAsTheReferenceStoresThem) {
  const std::vector<glm::mat4> poses = matricesOf(hardValues());
  ASSERT_EQ(firstBadJointReference(poses, 65504.0f), poses.size());
  for (const auto& [isa, name] : variants())
    for (PaletteFormat format : {PaletteFormat::kMatrix3x4F16, PaletteFormat::kMatrix3x4F32})
      for (uint32_t stride : {3u, 4u}) {  // A fourth texel per joint is left as it was.
        const size_t bytes = poses.size() * stride * bytesPerTexel(format);
        std::vector<uint8_t> fast(bytes, 0xA5), reference(bytes, 0xA5);
        Aabb box;
        box.extend(glm::vec3(1.0f));
        EXPECT_EQ(storePose(format, poses, stride, {}, 65504.0f, fast.data(), &box, isa),
                  poses.size())
            << name;
        EXPECT_TRUE(box.empty()) << name;  // No joint boxes.
        storeJointRowsReference(format, poses, stride, reference.data());
        size_t first_difference = bytes;
        for (size_t b = 0; b < bytes && first_difference == bytes; ++b)
          if (fast[b] != reference[b]) first_difference = b;
        EXPECT_EQ(first_difference, bytes)
            << name << ", " << paletteFormatName(format) << ", stride " << stride << ": byte "
            << first_difference << " of joint "
            << first_difference / (stride * bytesPerTexel(format));
      }
}

TEST(LivePoseRows, TheFirstBadMatrixIsTheReferencesOne) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  glm::mat4 good(1.0f);
  good[3] = glm::vec4(-65504.0f, 3.0f, 65504.0f, 1.0f);
  good[0][3] = -0.0f;  // Equal to 0.
  // Each bad matrix: one value changed. Rows 0 to 2 past the range or not finite; row 3 not
  // the identity's.
  std::vector<glm::mat4> bad;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      for (float x : r < 3 ? std::vector<float>{nan, inf, -inf, 65505.0f, -65504.01f}
                           : std::vector<float>{nan, 1e-30f, c == 3 ? 0.0f : 1.0f, -1.0f}) {
        glm::mat4 m = good;
        m[c][r] = x;
        bad.push_back(m);
      }
  std::vector<uint8_t> frame(61 * 3 * 16);
  Aabb box;
  for (const auto& [isa, name] : variants()) {
    const auto firstBad = [&, isa = isa](Span<const glm::mat4> poses, float range) {
      return storePose(PaletteFormat::kMatrix3x4F16, poses, 3, {}, range, frame.data(), &box, isa);
    };
    for (float range : {65504.0f, std::numeric_limits<float>::max()})
      for (size_t k = 0; k < bad.size(); ++k)
        for (size_t at : {size_t(0), size_t(5), size_t(60)}) {
          std::vector<glm::mat4> poses(61, good);
          poses[at] = bad[k];
          poses[60 - at / 2] = bad[k];  // A second one after it.
          const size_t want = firstBadJointReference(poses, range);
          if (range == 65504.0f) {  // Each is bad.
            EXPECT_LE(want, at) << "bad matrix " << k;
          }
          EXPECT_EQ(firstBad(poses, range), want) << name << ": bad matrix " << k << " at " << at;
        }
    const std::vector<glm::mat4> fine(61, good);
    EXPECT_EQ(firstBad(fine, 65504.0f), fine.size()) << name;
    EXPECT_EQ(firstBad(fine, 65503.0f), 0u) << name;
  }
}

// The pose's box four values at a time equals the reference's, joints with an empty box
// (nothing drawn follows them) adding nothing; the rows stored with it are the reference's.
TEST(LivePoseRows, ThePosesBoxIsTheReferences) {
  std::vector<glm::mat4> poses;
  std::vector<Aabb> boxes;
  const std::vector<float> v = hardValues();
  for (size_t k = 0; k + 20 < v.size() && poses.size() < 500; k += 21) {
    glm::mat4 m(1.0f);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r) m[c][r] = v[k + size_t(4 * c + r)] * 1e-3f;
    if ((poses.size() + 1) % 7 == 0) m[3] = glm::vec4(4000.0f, -4000.0f, 4000.0f, 1.0f);
    poses.push_back(m);
    Aabb b;
    if (poses.size() % 7 != 0) {  // Every seventh empty, and far from the others.
      b.extend(glm::vec3(v[k + 12], v[k + 13], v[k + 14]) * 1e-4f);
      b.extend(glm::vec3(v[k + 15], v[k + 16], v[k + 17]) * 1e-4f);
    }
    boxes.push_back(b);
  }
  const std::vector<JointBox> joints = jointBoxes(boxes);
  const std::vector<JointBox> none = jointBoxes(std::vector<Aabb>(poses.size()));
  for (const auto& [isa, name] : variants())
    for (PaletteFormat format : {PaletteFormat::kMatrix3x4F16, PaletteFormat::kMatrix3x4F32})
      for (size_t count : {poses.size(), poses.size() - 1}) {  // Even and odd (two at a time).
        const Span<const glm::mat4> some(poses.data(), count);
        const Span<const JointBox> boxed(joints.data(), count);
        const size_t bytes = count * 3 * bytesPerTexel(format);
        std::vector<uint8_t> fast(bytes), reference(bytes);
        Aabb box;
        ASSERT_EQ(storePose(format, some, 3, boxed, 65504.0f, fast.data(), &box, isa), count);
        storeJointRowsReference(format, some, 3, reference.data());
        const Aabb want = poseBoxReference(some, boxed);
        ASSERT_FALSE(want.empty());
        EXPECT_EQ(box.min, want.min) << name << ", " << count << " joints";
        EXPECT_EQ(box.max, want.max) << name << ", " << count << " joints";
        EXPECT_EQ(fast, reference) << name << ", " << count << " joints";
        ASSERT_EQ(storePose(format, some, 3, Span<const JointBox>(none.data(), count), 65504.0f,
                            fast.data(), &box, isa),
                  count);
        EXPECT_TRUE(box.empty()) << name;
      }
}

// Matrices whose products overflow to infinities of both signs carry a centre that is not a
// number: the box is then not a number either (the pose's bounds unknown, its clip's sphere
// culling it), in every variant, at every place among the joints, not a box that left the
// joint out.
TEST(LivePoseRows, AnOverflowingPoseHasNoBox) {
  Aabb unit;
  unit.extend(glm::vec3(1.0f));
  unit.extend(glm::vec3(2.0f));
  const std::vector<JointBox> joints = jointBoxes(std::vector<Aabb>(5, unit));
  glm::mat4 huge(1.0f);
  huge[0][0] = 3e38f;  // x: 3e38 * 1.5 + -3e38 * 1.5 = inf - inf.
  huge[1][0] = -3e38f;
  for (size_t at = 0; at < 5; ++at) {
    std::vector<glm::mat4> poses(5, glm::mat4(1.0f));
    poses[at] = huge;
    const Aabb want = poseBoxReference(poses, joints);
    EXPECT_TRUE(std::isnan(want.min.x) && std::isnan(want.max.x)) << "at " << at;
    for (const auto& [isa, name] : variants()) {
      std::vector<uint8_t> frame(5 * 3 * 16);
      Aabb box;
      ASSERT_EQ(storePose(PaletteFormat::kMatrix3x4F32, poses, 3, joints,
                          std::numeric_limits<float>::max(), frame.data(), &box, isa),
                poses.size());
      EXPECT_TRUE(std::isnan(box.min.x) && std::isnan(box.max.x)) << name << " at " << at;
    }
  }
}

}  // namespace
}  // namespace si::detail
