// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The crowd's per-frame work spread over threads (parallel_for.h): the same records, buckets and
// statistics whatever runs the tasks; records sorted by (LOD, worn mask) and buckets as runs;
// the STEP-clip lookup table; the 8-lane culling against the scalar one.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "crowd/crowd_test_helpers.h"
#include "crowd/cull_lanes.h"
#include "crowd/playback.h"
#include "crowd/record_lanes.h"
#include "si/crowd/parallel_for.h"

namespace si {
namespace {

using test::defaultCrowdDesc;
using test::defaultPalette;
using test::testCamera;

// A crowd of `n` instances scattered around and behind the camera (some beyond the far line),
// random masks over `sub_meshes` bits, clips, times, speeds, scales; a quarter crossfading.
std::unique_ptr<CrowdManager> randomCrowd(uint32_t n, uint32_t sub_meshes, uint64_t seed,
                                          uint32_t worker_threads) {
  auto crowd = std::make_unique<CrowdManager>();
  CrowdDesc d = defaultCrowdDesc();
  d.sub_mesh_count = sub_meshes;
  d.worker_threads = worker_threads;
  if (!crowd->init(d).isOk()) return nullptr;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const uint32_t clips = uint32_t(defaultPalette().clips.size());
  for (uint32_t i = 0; i < n; ++i) {
    InstanceDesc one;
    one.position = {u(rng) * 400.0 - 200.0, 0.0, u(rng) * 400.0 - 100.0};
    const double a = u(rng) * 6.283185307179586;
    one.rotation = glm::quat(float(std::cos(a / 2)), 0.0f, float(std::sin(a / 2)), 0.0f);
    one.scale = float(0.5 + u(rng));
    one.variation_mask = uint32_t(rng()) | 1u;
    one.clip = uint32_t(rng() % clips);
    one.time_seconds = u(rng) * 3.0;
    one.speed = float(0.5 + u(rng));
    one.loop_mode = (rng() & 3) == 0 ? LoopMode::kOnce : LoopMode::kDefault;
    InstanceHandle h;
    if (!crowd->add(one, &h).isOk()) return nullptr;
    if ((i & 3) == 0 && !crowd->crossfade(h, uint32_t(rng() % clips), 0.05 + u(rng)).isOk())
      return nullptr;
  }
  return crowd;
}

// Everything a frame hands out, for comparison.
struct FrameCopy {
  std::vector<uint8_t> records;
  std::vector<InstanceHandle> handles;
  std::vector<uint32_t> offsets, entries, run_offsets;
  std::vector<uint32_t> runs;  // first, count pairs.
  CrowdFrameStats stats;
};

FrameCopy copyFrame(const CrowdManager& c) {
  FrameCopy f;
  f.records.resize(c.records().size_bytes());
  if (!f.records.empty()) std::memcpy(f.records.data(), c.records().data(), f.records.size());
  f.handles.assign(c.visibleHandles().begin(), c.visibleHandles().end());
  f.offsets = c.bucketOffsets();
  f.entries = c.bucketEntries();
  f.run_offsets = c.bucketRunOffsets();
  for (const RecordRun& r : c.bucketRuns()) f.runs.insert(f.runs.end(), {r.first, r.count});
  f.stats = c.stats();
  return f;
}

void expectSameFrame(const FrameCopy& a, const FrameCopy& b, const char* what) {
  EXPECT_EQ(a.records, b.records) << what;
  EXPECT_EQ(a.handles.size(), b.handles.size()) << what;
  for (size_t i = 0; i < std::min(a.handles.size(), b.handles.size()); ++i)
    if (!(a.handles[i] == b.handles[i])) {
      ADD_FAILURE() << what << ": handle " << i << " differs";
      break;
    }
  EXPECT_EQ(a.offsets, b.offsets) << what;
  EXPECT_EQ(a.entries, b.entries) << what;
  EXPECT_EQ(a.run_offsets, b.run_offsets) << what;
  EXPECT_EQ(a.runs, b.runs) << what;
  EXPECT_EQ(a.stats.visible, b.stats.visible) << what;
  EXPECT_EQ(a.stats.culled_frustum, b.stats.culled_frustum) << what;
  EXPECT_EQ(a.stats.culled_distance, b.stats.culled_distance) << what;
  EXPECT_EQ(a.stats.bucket_entries, b.stats.bucket_entries) << what;
  EXPECT_EQ(0, std::memcmp(a.stats.per_lod, b.stats.per_lod, sizeof a.stats.per_lod)) << what;
}

TEST(ParallelUpdate, RecordsAndBucketsAreTheSameForOneTwoAndSevenThreads) {
  WorkerPool two(2), seven(7);
  const ParallelFor on_two = [&](uint32_t n, const ParallelTask& t) { two.run(n, t); };
  const ParallelFor on_seven = [&](uint32_t n, const ParallelTask& t) { seven.run(n, t); };
  // An engine's job system may run the tasks in any order: here, last first.
  const ParallelFor backwards = [](uint32_t n, const ParallelTask& t) {
    for (uint32_t i = n; i-- > 0;) t(i);
  };
  for (uint32_t sub_meshes : {4u, 32u}) {  // 32 random bits: past 64 masks, the fallback.
    for (uint64_t seed : {1u, 2u}) {
      const uint32_t n = 30000 + uint32_t(seed) * 777;  // 8 tasks, the last one partial.
      std::unique_ptr<CrowdManager> crowds[5];
      for (int k = 0; k < 5; ++k) {
        crowds[k] = randomCrowd(n, sub_meshes, seed, k == 4 ? 3u : 1u);
        ASSERT_NE(crowds[k], nullptr);
      }
      for (int frame = 0; frame < 4; ++frame) {
        // The camera moves, so LODs change through their hysteresis between frames.
        const Camera cam = testCamera({frame * 30.0, 2.0 + frame * 10.0, -20.0}, {0, 0, 100});
        ASSERT_TRUE(crowds[0]->update(0.3, cam, ParallelFor()).isOk());
        ASSERT_TRUE(crowds[1]->update(0.3, cam, on_two).isOk());
        ASSERT_TRUE(crowds[2]->update(0.3, cam, on_seven).isOk());
        ASSERT_TRUE(crowds[3]->update(0.3, cam, backwards).isOk());
        ASSERT_TRUE(crowds[4]->update(0.3, cam).isOk());  // Its own 3 workers.
        const FrameCopy one = copyFrame(*crowds[0]);
        ASSERT_GT(one.stats.visible, 1000u);
        ASSERT_GT(one.stats.culled_frustum + one.stats.culled_distance, 1000u);
        expectSameFrame(one, copyFrame(*crowds[1]), "2 threads");
        expectSameFrame(one, copyFrame(*crowds[2]), "7 threads");
        expectSameFrame(one, copyFrame(*crowds[3]), "tasks backwards");
        expectSameFrame(one, copyFrame(*crowds[4]), "worker_threads = 3");
      }
    }
  }
}

uint32_t wornOf(const CrowdManager& c, InstanceHandle h) {
  InstanceDesc d;
  EXPECT_TRUE(c.get(h, &d).isOk());
  const uint32_t s = c.desc().sub_mesh_count;
  return d.variation_mask & (s == 32 ? ~0u : (1u << s) - 1u);
}

TEST(ParallelUpdate, RecordsAreSortedByLodThenWornMaskAndRunsAreTheBuckets) {
  for (uint32_t sub_meshes : {4u, 32u}) {
    std::unique_ptr<CrowdManager> c = randomCrowd(20000, sub_meshes, 9, 2);
    ASSERT_NE(c, nullptr);
    ASSERT_TRUE(c->update(0.1, testCamera({0, 30, -40}, {0, 0, 80})).isOk());
    const Span<const InstanceHandle> handles = c->visibleHandles();
    ASSERT_EQ(handles.size(), c->records().size());
    std::vector<uint32_t> lod(handles.size()), worn(handles.size());
    for (size_t v = 0; v < handles.size(); ++v) {
      ASSERT_TRUE(c->lodOf(handles[v], &lod[v]).isOk());
      worn[v] = wornOf(*c, handles[v]);
    }
    const bool grouped = sub_meshes == 4;  // 15 masks: grouped; 32 random bits: the fallback.
    for (size_t v = 1; v < handles.size(); ++v) {
      ASSERT_LE(lod[v - 1], lod[v]);
      if (grouped && lod[v - 1] == lod[v]) {
        ASSERT_LE(worn[v - 1], worn[v]) << v;
      }
    }
    // Each bucket's entries are exactly the records of its LOD wearing its sub-mesh, in order,
    // and its runs hold the same entries.
    const uint32_t s_count = c->desc().sub_mesh_count;
    size_t runs_total = 0;
    for (uint32_t b = 0; b < c->bucketCount(); ++b) {
      std::vector<uint32_t> expected, from_runs;
      for (uint32_t v = 0; v < handles.size(); ++v)
        if (lod[v] == b / s_count && ((worn[v] >> (b % s_count)) & 1u)) expected.push_back(v);
      const std::vector<uint32_t> entries(c->bucketEntries().begin() + c->bucketOffsets()[b],
                                          c->bucketEntries().begin() + c->bucketOffsets()[b + 1]);
      EXPECT_EQ(entries, expected) << "bucket " << b;
      for (uint32_t r = c->bucketRunOffsets()[b]; r < c->bucketRunOffsets()[b + 1]; ++r) {
        const RecordRun run = c->bucketRuns()[r];
        EXPECT_GT(run.count, 0u);
        for (uint32_t k = 0; k < run.count; ++k) from_runs.push_back(run.first + k);
      }
      EXPECT_EQ(from_runs, expected) << "bucket " << b;
      runs_total += c->bucketRunOffsets()[b + 1] - c->bucketRunOffsets()[b];
    }
    // Grouped: the body (bit 0, worn by all) is one run per LOD, any sub-mesh at most 8 runs
    // (one per mask with its bit, joined where consecutive).
    if (grouped) {
      for (uint32_t l = 0; l < c->desc().lod_count; ++l)
        EXPECT_LE(c->bucketRunOffsets()[l * s_count + 1] - c->bucketRunOffsets()[l * s_count], 1u);
      EXPECT_LE(runs_total, size_t(c->bucketCount()) * 8);
    }
  }
}

TEST(ParallelUpdate, WorkerPoolRunsEveryTaskOnceInEverySection) {
  for (uint32_t threads : {1u, 2u, 7u}) {
    WorkerPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    std::vector<std::atomic<uint32_t>> hits(1000);
    for (uint32_t section = 0; section < 2000; ++section) {
      const uint32_t count = section % 2 ? 1000u : section % 7;  // Many short sections too.
      pool.run(count, [&](uint32_t i) { hits[i].fetch_add(1, std::memory_order_relaxed); });
    }
    // Sections of 1000 ran 1000 times; the short ones add to the first 6 indices.
    uint32_t short_hits[7] = {};
    for (uint32_t section = 0; section < 2000; section += 2)
      for (uint32_t i = 0; i < section % 7; ++i) ++short_hits[i];
    for (uint32_t i = 0; i < 1000; ++i)
      ASSERT_EQ(hits[i].load(), 1000u + (i < 7 ? short_hits[i] : 0u)) << threads << " " << i;
  }
  EXPECT_EQ(WorkerPool(0).threads(), 1u);
}

TEST(ParallelUpdate, WorkerThreadsPastTheLimitAreRefused) {
  CrowdDesc d = defaultCrowdDesc();
  d.worker_threads = 257;
  CrowdManager c;
  const Status s = c.init(d);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("worker_threads"), std::string::npos) << s.message();
}

TEST(ParallelUpdate, StepClipLookupMatchesSampleFramesEverywhere) {
  const BakedPalette& p = defaultPalette();
  CrowdManager c;
  ASSERT_TRUE(c.init(defaultCrowdDesc()).isOk());
  uint32_t stepped = 0;
  std::mt19937_64 rng(5);
  for (uint32_t clip = 0; clip < p.clips.size(); ++clip) {
    const BakedClip& bc = p.clips[clip];
    if (bc.frame_times_seconds.empty()) continue;
    ++stepped;
    std::vector<double> times = {0.0, double(bc.duration_seconds)};
    for (double t : bc.frame_times_seconds)  // Every key and its neighbours.
      times.insert(times.end(), {t, std::nextafter(t, -1.0), std::nextafter(t, 1e9)});
    for (uint32_t k = 0; k <= bc.frame_count * 8; ++k)  // Every grid point and between.
      times.push_back(double(k) / 8.0 * bc.frame_interval_seconds);
    for (int k = 0; k < 20000; ++k)
      times.push_back(std::uniform_real_distribution<double>(0.0, bc.duration_seconds)(rng));
    for (double t : times) {
      if (!(t >= 0.0 && t <= bc.duration_seconds)) continue;
      const FrameSample got = c.frameSample(clip, t), want = sampleFrames(bc, t);
      ASSERT_EQ(got.frame, want.frame) << bc.name << " t " << t;
      ASSERT_EQ(got.next_frame, want.next_frame) << bc.name << " t " << t;
      ASSERT_EQ(got.fraction, want.fraction) << bc.name << " t " << t;
    }
  }
  EXPECT_GT(stepped, 0u) << "the embedded character has a clip with STEP keys";
}

// The 8-lane selection against the scalar one, bit for bit, on hostile values: boundaries of
// the far line, the planes and the LOD lines, zero and huge scales, NaN and infinities.
// An instance so far from the camera that its squared distance passes a float (or its
// camera-relative position does) is culled by distance even without a far line, by the scalar
// and the 8-lane selection alike, and the crowd writes no record for it (the crowd API fuzzer
// once drew one at an infinite translation).
TEST(ParallelUpdate, PositionsPastAFloatAreCulledByDistanceWithoutAFarLine) {
  CrowdDesc cd = test::defaultCrowdDesc();
  cd.max_distance_radii = -1.0f;
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  const Camera camera = test::testCamera({0, 1.6, 0}, {0, 1, -10});
  for (double z : {-5.0, -2e19, -1e39, -1e300}) {
    InstanceDesc d;
    d.position = glm::dvec3(0.0, 0.0, z);
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
  }
  ASSERT_TRUE(crowd.update(0.0, camera).isOk());
  EXPECT_EQ(crowd.stats().visible, 1u);
  EXPECT_EQ(crowd.stats().culled_distance, 3u);
  for (const InstanceRecord& r : crowd.records())
    for (const auto& row : r.world_rows)
      for (float v : row) EXPECT_TRUE(std::isfinite(v));
  const CullParams p = crowd.cullParams(camera);
  cull::Selection sel;
  const glm::vec3 c(0.0f, 1.0f, 0.0f);
  EXPECT_FALSE(cull::select(glm::vec3(0.0f, 0.0f, -std::numeric_limits<float>::infinity()),
                            glm::quat(1, 0, 0, 0), 1.0f, c, 1.0f, c, 1.0f, p, &sel));
  EXPECT_TRUE(sel.culled_by_distance);
}

TEST(ParallelUpdate, EightLaneCullingSelectsExactlyWhatTheScalarOneSelects) {
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
  EXPECT_GE(__builtin_popcount(lods_seen), 4);
}

}  // namespace
}  // namespace si

namespace si {
namespace {

uint32_t bitsOf(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// The vectorised record (world rows, clip A's frame and fraction) against the scalar code it
// stands for: glm::mat3_cast * scale, then localTime and fastSample; lanes it cannot do must say
// so. Hostile times: negative, -0, huge, at multiples of the duration, NaN and infinities.
TEST(ParallelUpdate, VectorRecordsEqualTheScalarOnesOrDeferToThem) {
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

// A clip with frame times (frames at keys, STEP keys) finds its frame through the crowd's
// cell table: the same frame, fraction and mode as si::sampleFrames at every frame time, just
// before and after it, between frames, past the ends and at non-finite times.
TEST(ParallelUpdate, FrameTimesFoundThroughTheCellTableEqualSampleFrames) {
  BakedClip clip;
  clip.duration_seconds = 2.0f;
  clip.frame_times_seconds = {0.0, 0.01, 0.011, 0.3, 0.3, 0.31, 0.7, 1.0, 1.0005, 1.5, 2.0};
  clip.frame_count = uint32_t(clip.frame_times_seconds.size());
  clip.frame_interval_seconds = 0.5;  // The widest gap fits one grid interval.
  const detail::ClipTiming c = detail::makeClipTiming(clip);
  ASSERT_FALSE(c.uniform);
  ASSERT_FALSE(c.cell_frame.empty());
  std::vector<double> times = {-1.0, 2.5, 1e300, std::numeric_limits<double>::quiet_NaN(),
                               std::numeric_limits<double>::infinity()};
  for (double t : clip.frame_times_seconds)
    times.insert(times.end(), {t, std::nextafter(t, -1.0), std::nextafter(t, 3.0), t + 1e-4});
  for (int k = 0; k <= 4000; ++k) times.push_back(2.0 * k / 4000.0);
  for (double t : times) {
    const FrameSample want = sampleFrames(clip, t), got = detail::fastSample(c, clip, t);
    ASSERT_EQ(got.frame, want.frame) << t;
    ASSERT_EQ(got.next_frame, want.next_frame) << t;
    ASSERT_EQ(bitsOf(got.fraction), bitsOf(want.fraction)) << t;
    ASSERT_EQ(got.mode, want.mode) << t;
  }
}

}  // namespace
}  // namespace si
