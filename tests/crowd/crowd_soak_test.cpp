// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Long-run soak: a 10,000-instance crowd through a simulated span of frames at varying time
// steps (1/144, 1/60, 1/30 s, 0.1 s hitches, zero steps), with crossfades, speed changes and a
// steady churn of removes and adds. The clock must stay drift-free (every step is a multiple of
// 1/7200 s, so the exact clock is an integer count of ticks), untouched instances must play
// exactly where the analytic time says, and after a warm-up no call may allocate: memory does
// not grow. SI_SOAK_SECONDS sets the simulated span: the test run (CI) uses one hour; the week
// in docs/testing.md is SI_SOAK_SECONDS=604800 on a release build.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "crowd/crowd_test_helpers.h"

#include "crowd/allocation_counter.h"  // This binary counts its allocations.

namespace si {
namespace {

using test::defaultCrowdDesc;
using test::defaultPalette;

constexpr double kTick = 1.0 / 7200.0;            // Every step is a whole number of ticks.
constexpr uint32_t kStepTicks[] = {50, 120, 120, 120, 240, 720, 0};  // 1/144 .. 0.1 s, 0.

double soakSeconds() {
  const char* v = std::getenv("SI_SOAK_SECONDS");
  return v ? std::atof(v) : 3600.0;
}

TEST(CrowdSoak, TimeStaysExactAndMemoryDoesNotGrow) {
  const double span = soakSeconds();
  ASSERT_GT(span, 0.0);
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const BakedPalette& palette = defaultPalette();
  const uint32_t clips = uint32_t(palette.clips.size());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto randomDesc = [&] {
    InstanceDesc d;
    d.position = glm::dvec3(unit(rng) * 400.0 - 200.0, 0.0, unit(rng) * 400.0 - 200.0);
    d.clip = uint32_t(unit(rng) * clips) % clips;
    d.time_seconds = unit(rng) * 2.0;
    d.speed = float(0.5 + unit(rng));
    d.variation_mask = 1u | uint32_t(unit(rng) * 16.0);
    return d;
  };
  std::vector<InstanceHandle> churn;
  for (int i = 0; i < 9984; ++i) {
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(randomDesc(), &h).isOk());
    churn.push_back(h);
  }
  // Probes: never touched after being added, so their time follows from the clock alone.
  struct Probe {
    InstanceHandle handle;
    InstanceDesc desc;
  };
  std::vector<Probe> probes;
  for (uint32_t k = 0; k < 16; ++k) {
    Probe p;
    p.desc = randomDesc();
    p.desc.clip = k % clips;
    p.desc.loop_mode = k % 2 ? LoopMode::kLoop : LoopMode::kOnce;
    ASSERT_TRUE(crowd.add(p.desc, &p.handle).isOk());
    probes.push_back(p);
  }
  ASSERT_EQ(crowd.size(), 10000u);
  const Camera camera = test::testCamera({0.0, 30.0, -260.0}, {0.0, 0.0, 0.0});

  uint64_t ticks = 0, updates = 0, steps = 0;
  const uint64_t span_ticks = uint64_t(span / kTick);
  const uint64_t warm_up_ticks = span_ticks / 10;
  uint64_t next_update = 0;
  while (ticks < span_ticks) {
    const uint32_t step = kStepTicks[rng() % (sizeof(kStepTicks) / sizeof(kStepTicks[0]))];
    ticks += step;
    ++steps;
    if (ticks < next_update) {  // Between full updates only the clock moves (as with GPU culling).
      ASSERT_TRUE(crowd.advance(step * kTick).isOk());
      continue;
    }
    next_update = ticks + 7200;  // A full update every simulated second.
    ASSERT_TRUE(crowd.update(step * kTick, camera).isOk());
    ++updates;
    if (updates % 10 == 0) {  // Churn: 50 removed and 50 added, 100 crossfades, 20 new speeds.
      for (int k = 0; k < 50; ++k) {
        const size_t at = size_t(rng() % churn.size());
        ASSERT_TRUE(crowd.remove(churn[at]).isOk());
        ASSERT_TRUE(crowd.add(randomDesc(), &churn[at]).isOk());
      }
      for (int k = 0; k < 100; ++k)
        ASSERT_TRUE(crowd.crossfade(churn[rng() % churn.size()], uint32_t(rng() % clips),
                                    0.2 + unit(rng), unit(rng)).isOk());
      for (int k = 0; k < 20; ++k)
        ASSERT_TRUE(crowd.play(churn[rng() % churn.size()], uint32_t(rng() % clips),
                               unit(rng), float(0.5 + unit(rng))).isOk());
    }
    if (!g_counting && ticks >= warm_up_ticks) g_counting = true;  // From here on: no growth.
  }
  g_counting = false;
  ASSERT_TRUE(crowd.update(0.0, camera).isOk());

  // The clock: within 1 microsecond of the exact sum after every step.
  const double exact = double(ticks) / 7200.0;
  const double drift = std::fabs(crowd.clockSeconds() - exact);
  std::printf("[ soak     ] %.0f simulated s: %llu steps, %llu updates of %u instances; clock "
              "off by %.3g s; %zu allocations (%zu bytes) after the warm-up\n",
              exact, (unsigned long long)steps, (unsigned long long)updates, crowd.size(), drift,
              g_allocations.load(), g_allocated_bytes.load());
  EXPECT_LE(drift, 1e-6);
  EXPECT_EQ(g_allocations.load(), 0u);
  EXPECT_EQ(crowd.size(), 10000u);
  // The probes play where the analytic time says (long double for the reference).
  for (const Probe& p : probes) {
    const BakedClip& clip = palette.clips[p.desc.clip];
    const long double duration = clip.duration_seconds;
    long double t = (long double)p.desc.time_seconds + (long double)exact * p.desc.speed;
    if (p.desc.loop_mode == LoopMode::kLoop) {
      t = std::fmod(t, duration);
    } else {
      t = std::min(t, duration);
    }
    InstanceDesc got;
    ASSERT_TRUE(crowd.get(p.handle, &got).isOk());
    EXPECT_NEAR(got.time_seconds, double(t), 1e-6 * std::max(1.0, exact / 3600.0))
        << "probe clip " << clip.name;
  }
}

}  // namespace
}  // namespace si
