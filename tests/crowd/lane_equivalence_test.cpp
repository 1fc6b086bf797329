// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The crowd's 8-lane code against the scalar code it stands for, bit for bit, on hostile
// values: the culling (cull_lanes.h against cull::select) and the records (record_lanes.h against
// glm::mat3_cast, localTime and fastSample). Built twice: with the compiler's vector extensions
// in si_crowd_tests (suite VectorLanes), and with the portable lanes that MSVC builds use
// (SI_PORTABLE_LANES, lane_vectors.h) in si_portable_lanes_tests (suite PortableLanes), so the
// fallback stays tested on every run.
#include <gtest/gtest.h>

#include <bitset>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "crowd/crowd_test_helpers.h"
#include "crowd/cull_lanes.h"
#include "crowd/playback.h"
#include "crowd/record_lanes.h"

#if SI_LANES_EXTENSIONS
#define SI_LANES_SUITE VectorLanes
#else
#define SI_LANES_SUITE PortableLanes
#endif

namespace si {
namespace {

using test::defaultPalette;
using test::testCamera;

uint32_t bitsOf(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// The 8-lane selection against the scalar one, bit for bit, on hostile values: boundaries of
// the far line, the planes and the LOD lines, zero and huge scales, NaN and infinities.
TEST(SI_LANES_SUITE, EightLaneCullingSelectsExactlyWhatTheScalarOneSelects) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const float specials[] = {0.0f,
                            -0.0f,
                            1e-30f,
                            1e30f,
                            std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN(),
                            20.0f,
                            60.0f,
                            100.0f};
  uint32_t culled = 0, visible = 0, lods_seen = 0, beyond_far_line = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const Camera cam = testCamera({u(rng) * 5, 2 + u(rng), u(rng) * 5}, {u(rng) * 50, 0, 60});
    cull::Params p;
    p.planes = cam.frustumPlanes();
    p.radius = 1.0f + u(rng) * 0.5f;
    p.max_distance_radii = trial % 5 == 0 ? -1.0f : 100.0f;
    p.hysteresis = 0.05f;
    p.lod_count = 1 + uint32_t(trial % 8);
    for (uint32_t l = 0; l + 1 < p.lod_count; ++l) p.lod_lines[l] = 10.0f * float(l + 1);
    const cull::LodLines lines = cull::lodLines(p);
    cull::Lanes lanes;
    glm::vec3 rel[8], ca[8], cb[8];
    glm::quat q[8];
    float s[8], ra[8], rb[8];
    uint32_t prev[8];
    for (uint32_t k = 0; k < 8; ++k) {
      const float reach = trial % 3 == 0 ? 150.0f : 40.0f;
      rel[k] = glm::vec3(u(rng), u(rng) * 0.1f, u(rng) + 1.0f) * reach;
      if (uint32_t(trial % 7) == k) rel[k].z = specials[rng() % 9];
      q[k] = glm::normalize(glm::quat(u(rng), u(rng), u(rng), u(rng)));
      s[k] = uint32_t(trial % 11) == k ? specials[rng() % 9] : 0.5f + u(rng) * 0.4f;
      ca[k] = glm::vec3(u(rng), u(rng) + 1.0f, u(rng));
      // Odd lanes, and every lane of odd trials, have no second sphere (no crossfade).
      const bool one_sphere = k % 2 == 1 || trial % 2 == 1;
      cb[k] = one_sphere ? ca[k] : glm::vec3(u(rng), u(rng) + 1.0f, u(rng)) * 2.0f;
      ra[k] = 1.0f + u(rng) * 0.2f;
      rb[k] = one_sphere ? ra[k] : 1.5f;
      prev[k] = uint32_t(rng() % 9);  // Past lod_count too.
      lanes.rx[k] = rel[k].x, lanes.ry[k] = rel[k].y, lanes.rz[k] = rel[k].z;
      lanes.qx[k] = q[k].x, lanes.qy[k] = q[k].y, lanes.qz[k] = q[k].z, lanes.qw[k] = q[k].w;
      lanes.s[k] = s[k];
      lanes.ax[k] = ca[k].x, lanes.ay[k] = ca[k].y, lanes.az[k] = ca[k].z, lanes.ar[k] = ra[k];
      lanes.bx[k] = cb[k].x, lanes.by[k] = cb[k].y, lanes.bz[k] = cb[k].z, lanes.br[k] = rb[k];
      lanes.lod[k] = int32_t(prev[k]);
    }
    // The far-line test the frame builder runs before gathering, lane by lane.
    cull::LaneFloats d2;
    cull::LaneMasks far;
    cull::farLineLanes(p, lanes, 0, &d2, &far);
    bool any_near = false;
    // Odd trials as the frame builder calls it for 8 lanes none of which crossfades.
    cull::selectLanes(p, lines, lanes, 0, /*fades=*/trial % 2 == 0);
    for (uint32_t k = 0; k < 8; ++k) {
      const bool beyond = cull::beyondFarLine(rel[k], s[k], p);
      ASSERT_EQ(far[k], beyond ? -1 : 0) << "trial " << trial << " lane " << k;
      beyond_far_line += beyond;
      any_near |= !beyond;
      cull::Selection sel;
      sel.lod = prev[k];
      const bool same = k % 2 == 1 || trial % 2 == 1;
      const bool vis = same ? cull::select(rel[k], q[k], s[k], ca[k], ra[k], ca[k], ra[k], p, &sel)
                            : cull::select(rel[k], q[k], s[k], ca[k], ra[k], cb[k], rb[k], p, &sel);
      const int32_t want = vis                      ? cull::kLaneVisible
                           : sel.culled_by_distance ? cull::kLaneCulledByDistance
                                                    : cull::kLaneCulledByFrustum;
      ASSERT_EQ(lanes.result[k], want) << "trial " << trial << " lane " << k;
      if (vis) {
        ASSERT_EQ(uint32_t(lanes.lod[k]), sel.lod) << "trial " << trial << " lane " << k;
        lods_seen |= 1u << sel.lod;
      }
      (vis ? visible : culled) += 1;
    }
    ASSERT_EQ(cull::anyNearLane(p, lanes, 0), any_near) << "trial " << trial;
  }
  // The trials reach both outcomes, both sides of the far line and several LODs.
  EXPECT_GT(visible, 1000u);
  EXPECT_GT(culled, 1000u);
  EXPECT_GT(beyond_far_line, 500u);
  EXPECT_GE(std::bitset<32>(lods_seen).count(), 4u);
}

// The vectorised record (world rows, clip A's frame and fraction) against the scalar code it
// stands for: glm::mat3_cast * scale, then localTime and fastSample; lanes it cannot do must say
// so. Hostile times: negative, -0, huge, at multiples of the duration, NaN and infinities.
TEST(SI_LANES_SUITE, VectorRecordsEqualTheScalarOnesOrDeferToThem) {
  const BakedPalette& p = defaultPalette();
  std::vector<detail::ClipTiming> clips;
  for (const BakedClip& c : p.clips) clips.push_back(detail::makeClipTiming(c));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double hostile[] = {0.0, -0.0, 1e300, -1e300, 9.1e15, nan, inf, -inf, 1e-320};
  uint32_t vector_lanes = 0, deferred = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    detail::RecordLanes lanes = {};
    detail::Playback pb[detail::kRecordBlock];
    uint32_t clip_of[detail::kRecordBlock];
    glm::quat q[detail::kRecordBlock];
    const double clock = trial % 13 == 0 ? hostile[rng() % 9] : std::abs(u(rng)) * 1e4;
    for (uint32_t k = 0; k < detail::kRecordBlock; ++k) {
      uint32_t c = uint32_t(rng() % clips.size());
      while (!clips[c].uniform) c = uint32_t(rng() % clips.size());
      clip_of[k] = c;
      pb[k].clip = c;
      pb[k].loop = rng() % 3 == 0 ? LoopMode::kOnce : LoopMode::kLoop;
      pb[k].speed = float(std::abs(u(rng)) * (rng() % 5 == 0 ? 1e6 : 2.0));
      pb[k].start_clock = std::abs(u(rng)) * 1e4;
      pb[k].start_time = rng() % 7 == 0   ? hostile[rng() % 9]
                         : rng() % 5 == 0 ? double(clips[c].duration) * double(rng() % 9)
                                          : u(rng) * 10.0;
      q[k] = glm::normalize(glm::quat(float(u(rng)), float(u(rng)), float(u(rng)), float(u(rng))));
      lanes.qx[k] = q[k].x, lanes.qy[k] = q[k].y, lanes.qz[k] = q[k].z, lanes.qw[k] = q[k].w;
      lanes.s[k] = float(0.1 + std::abs(u(rng)) * 3.0);
      lanes.start_time[k] = pb[k].start_time, lanes.start_clock[k] = pb[k].start_clock;
      lanes.speed[k] = double(pb[k].speed);
      lanes.duration[k] = clips[c].duration, lanes.inv_duration[k] = clips[c].inv_duration;
      lanes.inv_interval[k] = clips[c].inv_interval;
      lanes.last_interval[k] = double(clips[c].last_interval);
      lanes.loop[k] = pb[k].loop == LoopMode::kLoop ? -1 : 0;
      lanes.scalar[k] = k == 5 ? -1 : 0;  // A lane already bound for the scalar path stays so.
    }
    for (uint32_t base = 0; base < detail::kRecordBlock; base += detail::kRecordLanes)
      detail::computeRecordLanes(clock, lanes, base);
    for (uint32_t k = 0; k < detail::kRecordBlock; ++k) {
      const glm::mat3 m = glm::mat3_cast(q[k]) * lanes.s[k];
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
          ASSERT_EQ(bitsOf(lanes.rows[row][col][k]), bitsOf(m[col][row])) << trial << " " << k;
      if (k == 5) {
        ASSERT_NE(lanes.scalar[k], 0);
      }
      if (lanes.scalar[k] != 0) {
        ++deferred;
        continue;
      }
      const detail::ClipTiming& c = clips[clip_of[k]];
      const double local = detail::localTime(pb[k], c, clock);
      // The lane's time: a clip with frame times finds its frame from it (frame_builder.cpp).
      uint64_t time_bits = 0, local_bits = 0;
      std::memcpy(&time_bits, &lanes.time[k], 8);
      std::memcpy(&local_bits, &local, 8);
      ASSERT_EQ(time_bits, local_bits) << trial << " " << k;
      const FrameSample want = detail::fastSample(c, p.clips[clip_of[k]], local);
      ASSERT_EQ(uint32_t(lanes.frame[k]), want.frame) << trial << " " << k;
      ASSERT_EQ(bitsOf(lanes.fraction[k]), bitsOf(want.fraction)) << trial << " " << k;
      ++vector_lanes;
    }
  }
  EXPECT_GT(vector_lanes, 100000u);
  EXPECT_GT(deferred, 3000u);  // The pinned lane, non-finite times, loops past 2^53 intervals.
}

}  // namespace
}  // namespace si
