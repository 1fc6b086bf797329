// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Cubic palettes in the crowd: every record's fraction word carries the interval mode of the
// frame it names, on the vector record path and the scalar one (crossfades), with one thread
// and two.
#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "crowd/crowd_test_helpers.h"

namespace si {
namespace {

using namespace test;

const BakedPalette& cubicPalette() {
  static const BakedPalette p = [] {
    BakeDesc d;
    d.rate_mode = RateMode::kFixed;
    d.sample_rate_hz = 30.0f;
    d.interpolation = InterpolationChoice::kCubic;
    BakedPalette out;
    if (!bakePalette(defaultCharacter(), d, &out, nullptr).isOk()) std::abort();
    return out;
  }();
  return p;
}

// The clip whose frames hold `texel` (the one with the largest first texel not above it).
uint32_t clipOfTexel(const BakedPalette& p, uint32_t texel) {
  uint32_t best = 0;
  for (uint32_t c = 0; c < p.clips.size(); ++c)
    if (p.clips[c].first_texel <= texel && p.clips[c].first_texel >= p.clips[best].first_texel)
      best = c;
  return best;
}

// Checks fraction word `word` of frame texel `texel` against the palette; counts the modes.
void expectMode(const BakedPalette& p, uint32_t texel, uint32_t word, uint32_t counts[4]) {
  const uint32_t c = clipOfTexel(p, texel);
  const uint32_t frame = (texel - p.clips[c].first_texel) / p.layout.frame_stride_texels;
  IntervalMode mode;
  const float fraction = unpackFraction(word, &mode);
  EXPECT_GE(fraction, 0.0f);
  EXPECT_LE(fraction, 1.0f);
  EXPECT_EQ(mode, intervalModeAt(p.clips[c], frame)) << p.clips[c].name << " frame " << frame;
  ++counts[uint32_t(mode)];
}

TEST(IntervalModeRecords, EveryRecordCarriesItsFramesMode) {
  const BakedPalette& p = cubicPalette();
  for (const BakedClip& c : p.clips) ASSERT_EQ(c.interpolation, FrameInterpolation::kCubic);
  CrowdDesc cd = defaultCrowdDesc();
  cd.palette = &p;
  std::mt19937 rng(7);
  for (bool two_threads : {false, true}) {
    SCOPED_TRACE(two_threads ? "two threads" : "one thread");
    CrowdManager crowd;
    ASSERT_TRUE(crowd.init(cd).isOk());
    std::vector<InstanceHandle> handles;
    for (int i = 0; i < 600; ++i) {
      InstanceDesc d;
      d.clip = uint32_t(i) % uint32_t(p.clips.size());
      const BakedClip& clip = p.clips[d.clip];
      // A third start in their first interval, a third in their last, the rest anywhere.
      const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
      d.time_seconds = i % 3 == 0   ? u * clip.frame_interval_seconds * 0.9
                       : i % 3 == 1 ? clip.duration_seconds * (1.0 - 1e-3 * u) - 1e-4
                                    : u * clip.duration_seconds;
      d.position = glm::dvec3((i % 30) * 1.5, 0, (i / 30) * 1.5);
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(d, &h).isOk());
      handles.push_back(h);
    }
    // A tenth crossfade (the scalar record path).
    for (size_t i = 0; i < handles.size(); i += 10)
      ASSERT_TRUE(crowd.crossfade(handles[i], uint32_t(i / 10) % uint32_t(p.clips.size()), 0.5,
                                  0.01)
                      .isOk());
    const Camera camera = testCamera({22, 40, -20}, {22, 0, 22});
    ParallelFor pf;
    if (two_threads)
      pf = [](uint32_t n, const ParallelTask& task) {
        std::thread t([&] {
          for (uint32_t k = 0; k < n; k += 2) task(k);
        });
        for (uint32_t k = 1; k < n; k += 2) task(k);
        t.join();
      };
    ASSERT_TRUE(crowd.update(1.0 / 60.0, camera, pf).isOk());
    ASSERT_GT(crowd.view().records().size(), 400u);
    uint32_t counts[4] = {};
    for (const InstanceRecord& r : crowd.view().records()) {
      expectMode(p, r.frames[0], r.blend[0], counts);
      expectMode(p, r.frames[2], r.blend[1], counts);
    }
    // The crowd reached full Catmull-Rom intervals and the one-sided ones at the ends.
    EXPECT_GT(counts[uint32_t(IntervalMode::kCubic)], 0u);
    EXPECT_GT(counts[uint32_t(IntervalMode::kCubicStartsHere)] +
                  counts[uint32_t(IntervalMode::kCubicEndsNext)],
              0u);
  }
}

}  // namespace
}  // namespace si
