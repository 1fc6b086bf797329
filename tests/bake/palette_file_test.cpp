// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "bake/bake_test_helpers.h"
#include "si/bake/palette_file.h"

namespace si {
namespace {

// The version 5 and 6 header: magic, then 12 u32 fields (the last the character's height),
// before the joint table.
constexpr size_t kHeaderBytes = 56;

// Where the clip records start: after the joint table and (version 6) the joint bounds.
size_t clipsStart(const BakedPalette& p) {
  return kHeaderBytes + 4 * p.palette_joints.size() + 4 + 24 * p.joint_bounds.size();
}

using test::smallPalette;

void fixChecksum(std::vector<uint8_t>* bytes) {
  const uint32_t crc = crc32(Span<const uint8_t>(bytes->data(), bytes->size() - 4));
  std::memcpy(bytes->data() + bytes->size() - 4, &crc, 4);
}

TEST(PaletteFile, RoundTripsBitExactly) {
  for (PaletteFormat f : {PaletteFormat::kMatrix3x4F32, PaletteFormat::kMatrix3x4F16,
                          PaletteFormat::kQuatTranslationF32})
  for (InterpolationChoice i : {InterpolationChoice::kLinear, InterpolationChoice::kCubic}) {
    const BakedPalette p = smallPalette(f, i);
    std::vector<uint8_t> bytes, again;
    ASSERT_TRUE(savePalette(p, &bytes).isOk());
    BakedPalette q;
    ASSERT_TRUE(loadPalette(bytes, &q).isOk());
    ASSERT_TRUE(savePalette(q, &again).isOk());
    EXPECT_EQ(bytes, again);
    EXPECT_EQ(q.format, p.format);
    EXPECT_EQ(q.texel_bytes, p.texel_bytes);
    EXPECT_EQ(q.palette_joints, p.palette_joints);
    EXPECT_EQ(q.skeleton_to_palette, p.skeleton_to_palette);
    ASSERT_EQ(q.joint_bounds.size(), p.palette_joints.size());
    for (size_t j = 0; j < p.joint_bounds.size(); ++j) {
      EXPECT_EQ(q.joint_bounds[j].min, p.joint_bounds[j].min);
      EXPECT_EQ(q.joint_bounds[j].max, p.joint_bounds[j].max);
    }
    ASSERT_EQ(q.clips.size(), p.clips.size());
    for (size_t c = 0; c < p.clips.size(); ++c) {
      EXPECT_EQ(q.clips[c].name, p.clips[c].name);
      EXPECT_EQ(q.clips[c].frame_count, p.clips[c].frame_count);
      EXPECT_EQ(q.clips[c].first_texel, p.clips[c].first_texel);
      EXPECT_EQ(q.clips[c].frame_times_seconds, p.clips[c].frame_times_seconds);
      EXPECT_EQ(q.clips[c].frame_interval_seconds, p.clips[c].frame_interval_seconds);
      EXPECT_EQ(q.clips[c].bounds.max, p.clips[c].bounds.max);
      EXPECT_EQ(q.clips[c].loop_mode, p.clips[c].loop_mode);
      EXPECT_EQ(q.clips[c].interpolation, p.clips[c].interpolation);
      EXPECT_EQ(q.clips[c].interval_modes, p.clips[c].interval_modes);
      EXPECT_EQ(q.clips[c].markers, p.clips[c].markers);
      EXPECT_EQ(q.clips[c].root_motion, p.clips[c].root_motion);
    }
    ASSERT_EQ(p.clips[1].markers.size(), 2u);  // The markers were exercised,
    ASSERT_FALSE(p.clips[2].root_motion.empty());  // and the root motion.
    EXPECT_EQ(q.layout.border_frames, p.layout.border_frames);
    EXPECT_EQ(q.layout.border_frames, i == InterpolationChoice::kCubic ? 1u : 0u);
    EXPECT_EQ(q.layout.clip_first_texel, p.layout.clip_first_texel);
    EXPECT_FALSE(p.clips[0].frame_times_seconds.empty());  // The STEP clip was exercised.
  }
}

TEST(PaletteFile, EveryTruncationIsRejected) {
  std::vector<uint8_t> bytes;
  ASSERT_TRUE(savePalette(smallPalette(), &bytes).isOk());
  for (size_t n = 0; n < bytes.size(); ++n) {
    BakedPalette q;
    const Status s = loadPalette(Span<const uint8_t>(bytes.data(), n), &q);
    ASSERT_EQ(s.code(), StatusCode::kCorrupt) << "prefix of " << n << " bytes";
    ASSERT_TRUE(q.clips.empty());
  }
}

TEST(PaletteFile, EveryByteAndBitFlipIsRejected) {
  std::vector<uint8_t> bytes;
  ASSERT_TRUE(savePalette(smallPalette(), &bytes).isOk());
  for (size_t i = 0; i < bytes.size(); ++i) {
    for (uint8_t mask : {uint8_t(0xFF), uint8_t(1u << (i % 8))}) {
      std::vector<uint8_t> bad = bytes;
      bad[i] ^= mask;
      BakedPalette q;
      const Status s = loadPalette(bad, &q);
      ASSERT_FALSE(s.isOk()) << "byte " << i << " mask " << int(mask);
      ASSERT_TRUE(s.code() == StatusCode::kCorrupt || s.code() == StatusCode::kUnsupported)
          << s.toString();
    }
  }
}

TEST(PaletteFile, TrailingBytesAndOtherVersionsAreRejected) {
  std::vector<uint8_t> bytes;
  ASSERT_TRUE(savePalette(smallPalette(), &bytes).isOk());
  BakedPalette q;
  std::vector<uint8_t> longer = bytes;
  longer.push_back(0);
  EXPECT_EQ(loadPalette(longer, &q).code(), StatusCode::kCorrupt);
  for (uint8_t version : {0, 7}) {
    std::vector<uint8_t> other = bytes;
    other[8] = version;
    fixChecksum(&other);
    EXPECT_EQ(loadPalette(other, &q).code(), StatusCode::kUnsupported);
  }
}

// Older versions still load: version 5 (before joint bounds) without them; version 4 (before
// morph targets: no morph target count in the header) without them; version 3 (before root motion)
// without it; version 2 (before animation markers: no marker fields in the clip records) with the
// same clips and no markers; version 1 (before cubic interpolation: no border-frame field in the
// header, no interpolation fields either) as linear palettes.
TEST(PaletteFile, VersionOneToFiveFilesStillLoad) {
  const BakedPalette p = smallPalette();
  std::vector<uint8_t> bytes;
  ASSERT_TRUE(savePalette(p, &bytes).isOk());
  ASSERT_FALSE(p.joint_bounds.empty());
  for (uint8_t version : {1, 2, 3, 4, 5}) {
    SCOPED_TRACE(int(version));
    const bool v1 = version == 1, markers_kept = version >= 3, root_motion_kept = version >= 4;
    std::vector<uint8_t> old(bytes.begin(), bytes.begin() + 36);  // Up to the stride.
    old[8] = version;
    if (!v1) old.insert(old.end(), bytes.begin() + 36, bytes.begin() + 40);  // Border frames.
    if (version == 5) old.insert(old.end(), bytes.begin() + 40, bytes.begin() + 44);  // Morphs.
    size_t at = 44;  // Past the morph target count.
    const size_t joints_end = kHeaderBytes + 4 * p.palette_joints.size();
    old.insert(old.end(), bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(joints_end));
    at = clipsStart(p);  // The joint bounds skipped.
    for (const BakedClip& c : p.clips) {
      size_t kept = 4 + c.name.size() + 4 + 4 + 8 + 4 + 4 + 8 * c.frame_times_seconds.size();
      if (!v1) kept += 8 + c.interval_modes.size();            // v2 has the interpolation,
      size_t markers = 4;
      for (const AnimationMarker& m : c.markers) markers += 12 + m.name.size();
      if (markers_kept) kept += markers;  // v3 the markers.
      old.insert(old.end(), bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + kept));
      // Skip what the version lacks.
      at += kept + (v1 ? 8 + c.interval_modes.size() : 0) + (markers_kept ? 0 : markers);
      const size_t root_motion = 4 + 12 * c.root_motion.size();  // v4 the root motion.
      if (root_motion_kept)
        old.insert(old.end(), bytes.begin() + std::ptrdiff_t(at),
                   bytes.begin() + std::ptrdiff_t(at + root_motion));
      at += root_motion;
      old.insert(old.end(), bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + 40));
      at += 40;
    }
    old.insert(old.end(), bytes.begin() + std::ptrdiff_t(at), bytes.end());
    fixChecksum(&old);
    BakedPalette q;
    const Status s = loadPalette(old, &q);
    ASSERT_TRUE(s.isOk()) << s.toString();
    EXPECT_EQ(q.texel_bytes, p.texel_bytes);
    EXPECT_EQ(q.layout.border_frames, 0u);
    EXPECT_EQ(q.layout.morph_target_count, 0u);
    EXPECT_TRUE(q.joint_bounds.empty());
    for (size_t c = 0; c < q.clips.size(); ++c) {
      EXPECT_EQ(q.clips[c].interpolation, FrameInterpolation::kLinear);
      EXPECT_EQ(q.clips[c].root_motion,
                root_motion_kept ? p.clips[c].root_motion : std::vector<glm::vec3>());
      EXPECT_EQ(q.clips[c].markers,
                markers_kept ? p.clips[c].markers : std::vector<AnimationMarker>());
    }
  }
}

TEST(PaletteFile, MarkersThatWouldNotLoadAreNotWritten) {
  BakedPalette p = smallPalette();
  std::vector<uint8_t> bytes;
  p.clips[1].markers.push_back({0.5, std::string(5000, 'x')});  // Longer than a name may be.
  EXPECT_EQ(savePalette(p, &bytes).code(), StatusCode::kInvalidArgument);
  p.clips[1].markers.back().name = "";  // Empty: BakedPalette::validate() refuses it.
  EXPECT_EQ(savePalette(p, &bytes).code(), StatusCode::kInvalidArgument);
  p.clips[1].markers.back() = {1.5, "late"};  // Past the clip's 1 s.
  const Status late = savePalette(p, &bytes);
  EXPECT_EQ(late.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(late.message().find("marker 2 'late'"), std::string::npos) << late.message();
  EXPECT_TRUE(bytes.empty());
}

TEST(PaletteFile, InconsistentFilesWithValidChecksumsAreRejected) {
  std::vector<uint8_t> bytes;
  const BakedPalette p = smallPalette();
  ASSERT_TRUE(savePalette(p, &bytes).isOk());
  const auto patched = [&](size_t offset, uint32_t value) {
    std::vector<uint8_t> b = bytes;
    std::memcpy(b.data() + offset, &value, 4);
    fixChecksum(&b);
    BakedPalette q;
    return loadPalette(b, &q).code();
  };
  // Header fields: magic(8) version(4) format(4) width(4) height(4) joints(4) tpj(4) stride(4)
  // border frames(4) morph targets(4) skeleton joints(4) clips(4) height(4).
  EXPECT_EQ(patched(16, p.layout.width * 2), StatusCode::kCorrupt);   // Width vs. layout.
  EXPECT_EQ(patched(16, 3), StatusCode::kCorrupt);                    // Not a power of two.
  EXPECT_EQ(patched(20, 1u << 30), StatusCode::kCorrupt);             // Oversized height.
  EXPECT_EQ(patched(12, 9), StatusCode::kCorrupt);                    // Unknown format.
  EXPECT_EQ(patched(12, 0x2701), StatusCode::kCorrupt);  // Found by the fuzzer: low byte valid.
  EXPECT_EQ(patched(24, 200), StatusCode::kCorrupt);                  // Joints > skeleton.
  EXPECT_EQ(patched(36, 2), StatusCode::kCorrupt);                    // Border frames > 1.
  EXPECT_EQ(patched(36, 1), StatusCode::kCorrupt);                    // Border frames vs. size.
  EXPECT_EQ(patched(40, 257), StatusCode::kCorrupt);                  // Morph targets > 256.
  EXPECT_EQ(patched(40, 4), StatusCode::kCorrupt);                    // Morph targets vs. size.
  EXPECT_EQ(patched(44, 0xFFFFFFFFu), StatusCode::kCorrupt);          // Absurd skeleton.
  EXPECT_EQ(patched(48, 0xFFFFFFFFu), StatusCode::kCorrupt);          // Absurd clip count.
  EXPECT_EQ(patched(48, 1), StatusCode::kCorrupt);                    // Clip table vs. size.
  EXPECT_EQ(patched(52, 0xFFFFFFFFu), StatusCode::kCorrupt);          // NaN height.
  EXPECT_EQ(patched(56, 7), StatusCode::kCorrupt);                    // Joint table out of range.
  // The joint bounds: a count other than 0 or the joints', a NaN, a box inverted on x.
  const size_t bounds_at = kHeaderBytes + 4 * p.palette_joints.size();
  ASSERT_EQ(p.joint_bounds.size(), p.palette_joints.size());
  EXPECT_EQ(patched(bounds_at, 1), StatusCode::kCorrupt);
  EXPECT_EQ(patched(bounds_at, 0xFFFFFFFFu), StatusCode::kCorrupt);
  EXPECT_EQ(patched(bounds_at + 4, 0x7FC00000u), StatusCode::kCorrupt);  // min.x NaN.
  EXPECT_EQ(patched(bounds_at + 4, 0x49742400u), StatusCode::kCorrupt);  // min.x 1e6 > max.x.
  // The first clip's frame count (after its name) claims more frames than the data holds.
  const size_t clip0 = clipsStart(p);
  const size_t frames_at = clip0 + 4 + p.clips[0].name.size() + 4 + 4 + 8;
  EXPECT_EQ(patched(frames_at, 1u << 20), StatusCode::kCorrupt);
  EXPECT_EQ(patched(frames_at, 0), StatusCode::kCorrupt);
}

TEST(PaletteFile, FilesAndErrors) {
  const BakedPalette p = smallPalette();
  const std::string path = ::testing::TempDir() + "si_palette_test.sipal";
  ASSERT_TRUE(savePaletteFile(p, path).isOk());
  BakedPalette q;
  ASSERT_TRUE(loadPaletteFile(path, &q).isOk());
  EXPECT_EQ(q.texel_bytes, p.texel_bytes);
  std::remove(path.c_str());
  EXPECT_EQ(loadPaletteFile(path, &q).code(), StatusCode::kIo);
  EXPECT_EQ(savePaletteFile(p, "/nonexistent/dir/x.sipal").code(), StatusCode::kIo);
  EXPECT_EQ(loadPalette({}, nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(savePalette(p, nullptr).code(), StatusCode::kInvalidArgument);
  BakedPalette broken = p;
  broken.texel_bytes.pop_back();
  std::vector<uint8_t> bytes;
  EXPECT_EQ(savePalette(broken, &bytes).code(), StatusCode::kInvalidArgument);
}

// The fuzzer's find (tests/regressions/inputs/palette-clip-timing-ub.sipal): a clip whose frame
// interval disagrees with its duration and frame count by orders of magnitude loaded, then
// si::sampleFrames converted 2e232 to uint32_t. Every such file must now be refused.
TEST(PaletteFile, ClipTimingThatDisagreesWithItsFramesIsRejected) {
  std::vector<uint8_t> bytes;
  const BakedPalette p = smallPalette();
  ASSERT_TRUE(savePalette(p, &bytes).isOk());
  // Clip 1 ("swing", uniform grid): name length, name, loop, duration (f32), interval (f64).
  size_t clip1 = clipsStart(p);
  // Its marker count and root motion count, 4 bytes each, before its bounds.
  ASSERT_TRUE(p.clips[0].markers.empty() && p.clips[0].root_motion.empty());
  clip1 += 4 + p.clips[0].name.size() + 4 + 4 + 8 + 4 + 4 + 8 * p.clips[0].frame_times_seconds.size() + 8 + 4 + 4 + 40;
  const size_t duration_at = clip1 + 4 + p.clips[1].name.size() + 4;
  const size_t interval_at = duration_at + 4;
  const auto load = [&](size_t offset, const void* value, size_t n) {
    std::vector<uint8_t> b = bytes;
    std::memcpy(b.data() + offset, value, n);
    fixChecksum(&b);
    BakedPalette q;
    const Status s = loadPalette(b, &q);
    EXPECT_TRUE(q.clips.empty());
    return s;
  };
  float duration = 0.0f;
  double interval = 0.0;
  std::memcpy(&duration, bytes.data() + duration_at, 4);
  std::memcpy(&interval, bytes.data() + interval_at, 8);
  ASSERT_FLOAT_EQ(duration, p.clips[1].duration_seconds);  // The offsets are right.
  ASSERT_DOUBLE_EQ(interval, p.clips[1].frame_interval_seconds);
  for (double bad : {1e-230, interval * 0.5, interval * 1.01, 1e30, 0.0, -interval}) {
    const Status s = load(interval_at, &bad, 8);
    EXPECT_EQ(s.code(), StatusCode::kCorrupt) << "interval " << bad << ": " << s.toString();
  }
  for (float bad : {duration * 1000.0f, duration * 0.5f, 2e9f, 0.0f}) {
    const Status s = load(duration_at, &bad, 4);
    EXPECT_EQ(s.code(), StatusCode::kCorrupt) << "duration " << bad << ": " << s.toString();
  }
  // Clip 0 ("step"): frame times out of order, or three times the same.
  const size_t times_at = clipsStart(p) + 4 + p.clips[0].name.size() + 4 + 4 + 8 + 4 + 4;
  const std::vector<double>& times = p.clips[0].frame_times_seconds;
  ASSERT_GE(times.size(), 4u);
  const double reordered[2] = {times[2], times[1]};
  EXPECT_EQ(load(times_at + 8, reordered, 16).code(), StatusCode::kCorrupt);
  const double tripled[3] = {times[1], times[1], times[1]};
  EXPECT_EQ(load(times_at + 8, tripled, 24).code(), StatusCode::kCorrupt);
  // A texel that is not finite.
  const uint32_t nan_bits = 0x7FC00000u;
  EXPECT_EQ(load(bytes.size() - 4 - p.texel_bytes.size() + 16 * 4, &nan_bits, 4).code(),
            StatusCode::kCorrupt);
}

TEST(PaletteFile, Crc32MatchesTheStandardCheckValue) {
  const char* check = "123456789";
  EXPECT_EQ(crc32(Span<const uint8_t>(reinterpret_cast<const uint8_t*>(check), 9)), 0xCBF43926u);
}

}  // namespace
}  // namespace si
