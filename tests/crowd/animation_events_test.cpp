// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Animation events: clip markers passed by instances between updates, across loops, large
// steps, one-shot clips, crossfades, restarts and thread counts.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "crowd/crowd_test_helpers.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/parallel_for.h"

namespace si {
namespace {

using test::defaultCrowdDesc;
using test::defaultPalette;
using test::testCamera;

// Passes of marker `t` by unwrapped clip time in (u0, u1] (or [u0, u1]) of a loop of `d`,
// counted by stepping through the loops one by one.
uint32_t bruteLoopPasses(double t, double d, double u0, double u1, bool inclusive) {
  uint32_t n = 0;
  for (double k = std::floor((u0 - t) / d) - 1; t + k * d <= u1; k += 1.0)
    if (inclusive ? t + k * d >= u0 : t + k * d > u0) ++n;
  return n;
}

uint32_t totalCount(const CrowdManager& c, uint32_t marker) {
  uint32_t n = 0;
  for (const AnimationEvent& e : c.events())
    if (e.marker == marker) n += e.count;
  return n;
}

uint32_t loopingClip() {
  const BakedPalette& p = defaultPalette();
  for (uint32_t c = 0; c < p.clips.size(); ++c)
    if (p.clips[c].loop_mode == LoopMode::kLoop && p.clips[c].duration_seconds > 0.5f) return c;
  return 0;
}

TEST(AnimationEvents, LoopingClipCountsEveryPassInSmallAndLargeSteps) {
  const uint32_t clip = loopingClip();
  const double d = defaultPalette().clips[clip].duration_seconds;
  ASSERT_EQ(defaultPalette().clips[clip].loop_mode, LoopMode::kLoop);
  const Camera cam = testCamera({0, 2, -10}, {0, 1, 0});
  for (double step : {0.016, 0.37 * d, 10.5 * d}) {
    CrowdManager c;
    ASSERT_TRUE(c.init(defaultCrowdDesc()).isOk());
    uint32_t marker = 0;
    ASSERT_TRUE(c.addClipMarker(clip, 0.25 * d, "step", &marker).isOk());
    InstanceDesc one;
    one.clip = clip;
    one.time_seconds = 0.1 * d;
    one.speed = 1.3f;
    InstanceHandle h;
    ASSERT_TRUE(c.add(one, &h).isOk());
    uint32_t got = 0;
    double clock = 0.0;
    while (clock < 21.0 * d) {
      ASSERT_TRUE(c.update(step, cam).isOk());
      clock += step;
      for (const AnimationEvent& e : c.events()) {
        EXPECT_EQ(e.instance, h);
        EXPECT_EQ(c.clipMarkers()[e.marker].name, "step");
      }
      got += totalCount(c, marker);
    }
    // From the start (inclusive) to the end of playback in unwrapped time.
    const double u1 = 0.1 * d + c.clockSeconds() * 1.3;
    EXPECT_EQ(got, bruteLoopPasses(0.25 * d, d, 0.1 * d, u1, true)) << "step " << step;
    EXPECT_GT(got, 20u);
  }
}

TEST(AnimationEvents, StartIsInclusiveOnceAndOneShotClipsFireOnce) {
  const uint32_t clip = loopingClip();
  const double d = defaultPalette().clips[clip].duration_seconds;
  const Camera cam = testCamera({0, 2, -10}, {0, 1, 0});
  CrowdManager c;
  ASSERT_TRUE(c.init(defaultCrowdDesc()).isOk());
  uint32_t at_start = 0, at_end = 0;
  ASSERT_TRUE(c.addClipMarker(clip, 0.0, "start", &at_start).isOk());
  ASSERT_TRUE(c.addClipMarker(clip, d, "end", &at_end).isOk());
  InstanceDesc one;
  one.clip = clip;
  one.loop_mode = LoopMode::kOnce;
  InstanceHandle h;
  ASSERT_TRUE(c.add(one, &h).isOk());
  ASSERT_TRUE(c.update(0.0, cam).isOk());  // A zero step still reports the start.
  EXPECT_EQ(totalCount(c, at_start), 1u);
  ASSERT_TRUE(c.update(0.0, cam).isOk());  // Once only.
  EXPECT_EQ(totalCount(c, at_start), 0u);
  uint32_t ends = 0;
  for (int k = 0; k < 100; ++k) {  // Well past the end: the end marker fires once.
    ASSERT_TRUE(c.update(d / 30.0, cam).isOk());
    ends += totalCount(c, at_end);
    EXPECT_EQ(totalCount(c, at_start), 0u);
  }
  EXPECT_EQ(ends, 1u);
  // play() restarts, now looping (the clip's mode) at half speed: the start fires again. In a
  // loop the end is the next loop's start, so both markers fire at both instants.
  ASSERT_TRUE(c.play(h, clip, 0.0, 0.5f).isOk());
  ASSERT_TRUE(c.update(d, cam).isOk());  // [0, d/2]: the start.
  EXPECT_EQ(totalCount(c, at_start), 1u);
  EXPECT_EQ(totalCount(c, at_end), 1u);
  ASSERT_TRUE(c.update(0.5 * d, cam).isOk());  // (d/2, 3d/4]: nothing.
  EXPECT_TRUE(c.events().empty());
  ASSERT_TRUE(c.update(0.5 * d, cam).isOk());  // (3d/4, d]: the wrap.
  EXPECT_EQ(totalCount(c, at_start), 1u);
  EXPECT_EQ(totalCount(c, at_end), 1u);
}

TEST(AnimationEvents, CrossfadeReportsTheClipFadingOutUntilTheFadeEnds) {
  const uint32_t clip = loopingClip();
  const double d = defaultPalette().clips[clip].duration_seconds;
  const uint32_t other = clip == 0 ? 1u : 0u;
  const Camera cam = testCamera({0, 2, -10}, {0, 1, 0});
  CrowdManager c;
  ASSERT_TRUE(c.init(defaultCrowdDesc()).isOk());
  uint32_t m = 0;
  ASSERT_TRUE(c.addClipMarker(clip, 0.5 * d, "mid", &m).isOk());
  InstanceDesc one;
  one.clip = clip;
  InstanceHandle h;
  ASSERT_TRUE(c.add(one, &h).isOk());
  ASSERT_TRUE(c.update(0.1 * d, cam).isOk());
  // Fade out over 3 loops of the clip: it keeps playing (and passing its marker) until then.
  ASSERT_TRUE(c.crossfade(h, other, 3.0 * d).isOk());
  const double fade_from_u = 0.1 * d;  // Its clip time when the fade starts.
  uint32_t got = 0;
  for (int k = 0; k < 60; ++k) {
    ASSERT_TRUE(c.update(0.1 * d, cam).isOk());
    got += totalCount(c, m);
  }
  EXPECT_EQ(got, bruteLoopPasses(0.5 * d, d, fade_from_u, fade_from_u + 3.0 * d, false));
  EXPECT_EQ(got, 3u);
}

TEST(AnimationEvents, SameEventsForAnyThreadCountAndNoneWithoutMarkers) {
  WorkerPool seven(7);
  const ParallelFor on_seven = [&](uint32_t n, const ParallelTask& t) { seven.run(n, t); };
  const Camera cam = testCamera({0, 30, -40}, {0, 0, 80});
  std::unique_ptr<CrowdManager> crowds[2];
  for (auto& c : crowds) {
    c = std::make_unique<CrowdManager>();
    ASSERT_TRUE(c->init(defaultCrowdDesc()).isOk());
    std::vector<glm::dvec3> positions;
    for (int i = 0; i < 20000; ++i) positions.push_back(glm::dvec3(i % 150, 0, i / 150) * 1.5);
    RandomCrowdDesc r;
    r.positions = positions;
    ASSERT_TRUE(c->addRandom(r, nullptr).isOk());
    ASSERT_TRUE(c->update(0.1, cam).isOk());
    EXPECT_TRUE(c->events().empty());
    for (uint32_t clip = 0; clip < defaultPalette().clips.size(); ++clip)
      ASSERT_TRUE(
          c->addClipMarker(clip, defaultPalette().clips[clip].duration_seconds * 0.5, "half")
              .isOk());
  }
  size_t total = 0;
  for (int frame = 0; frame < 5; ++frame) {
    ASSERT_TRUE(crowds[0]->update(0.2, cam, ParallelFor()).isOk());
    ASSERT_TRUE(crowds[1]->update(0.2, cam, on_seven).isOk());
    const Span<const AnimationEvent> a = crowds[0]->events(), b = crowds[1]->events();
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(a[k].instance, b[k].instance);
      ASSERT_EQ(a[k].marker, b[k].marker);
      ASSERT_EQ(a[k].count, b[k].count);
    }
    total += a.size();
  }
  EXPECT_GT(total, 1000u);  // Culled instances report too: events are about time, not sight.
}

TEST(AnimationEvents, BadMarkersAreRefused) {
  CrowdManager c;
  EXPECT_EQ(c.addClipMarker(0, 0.0, "x").code(), StatusCode::kInvalidArgument);  // No init.
  ASSERT_TRUE(c.init(defaultCrowdDesc()).isOk());
  const uint32_t clips = uint32_t(defaultPalette().clips.size());
  EXPECT_EQ(c.addClipMarker(clips, 0.0, "x").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(c.addClipMarker(0, -0.1, "x").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(c.addClipMarker(0, 1e9, "x").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(c.addClipMarker(0, std::nan(""), "x").code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(c.clipMarkers().empty());
}

// The palette's markers (BakedClip::markers: from the character's clips, a glTF file's
// extras or a palette file) are the crowd's from init() on, before those added.
TEST(AnimationEvents, ThePalettesMarkersAreTheCrowdsFromInit) {
  const uint32_t clip = loopingClip();
  BakedPalette p = defaultPalette();
  const double d = p.clips[clip].duration_seconds;
  p.clips[clip].markers = {{0.25 * d, "left"}, {0.75 * d, "right"}};
  ASSERT_TRUE(p.validate().isOk());
  CrowdDesc cd = defaultCrowdDesc();
  cd.palette = &p;
  CrowdManager c;
  ASSERT_TRUE(c.init(cd).isOk());
  ASSERT_EQ(c.clipMarkers().size(), 2u);
  EXPECT_EQ(c.clipMarkers()[1].name, "right");
  EXPECT_EQ(c.clipMarkers()[1].clip, clip);
  EXPECT_EQ(c.clipMarkers()[1].time_seconds, 0.75 * d);
  uint32_t added = 0;
  ASSERT_TRUE(c.addClipMarker(clip, 0.5 * d, "middle", &added).isOk());
  EXPECT_EQ(added, 2u);
  InstanceDesc one;
  one.clip = clip;
  InstanceHandle h;
  ASSERT_TRUE(c.add(one, &h).isOk());
  ASSERT_TRUE(c.update(0.0, testCamera({0, 2, -10}, {0, 1, 0})).isOk());
  ASSERT_TRUE(c.update(0.8 * d, testCamera({0, 2, -10}, {0, 1, 0})).isOk());  // Past all three.
  EXPECT_EQ(totalCount(c, 0), 1u);
  EXPECT_EQ(totalCount(c, 1), 1u);
  EXPECT_EQ(totalCount(c, 2), 1u);
}

}  // namespace
}  // namespace si
