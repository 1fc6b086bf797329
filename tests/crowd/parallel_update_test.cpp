// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The crowd's per-frame work spread over threads (parallel_for.h): the same records, buckets and
// statistics whatever runs the tasks; records sorted by (LOD, worn mask) and buckets as runs;
// the STEP-clip lookup table (the 8-lane code against the scalar: lane_equivalence_test.cpp).
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
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
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
  f.records.resize(c.view().records().size_bytes());
  if (!f.records.empty())
    std::memcpy(f.records.data(), c.view().records().data(), f.records.size());
  f.handles.assign(c.view().visibleHandles().begin(), c.view().visibleHandles().end());
  f.offsets = c.view().bucketOffsets();
  f.entries = c.view().bucketEntries();
  f.run_offsets = c.view().bucketRunOffsets();
  for (const RecordRun& r : c.view().bucketRuns()) f.runs.insert(f.runs.end(), {r.first, r.count});
  f.stats = c.view().stats();
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
    const Span<const InstanceHandle> handles = c->view().visibleHandles();
    ASSERT_EQ(handles.size(), c->view().records().size());
    std::vector<uint32_t> lod(handles.size()), worn(handles.size());
    for (size_t v = 0; v < handles.size(); ++v) {
      ASSERT_TRUE(c->view().lodOf(handles[v], &lod[v]).isOk());
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
    for (uint32_t b = 0; b < c->view().bucketCount(); ++b) {
      std::vector<uint32_t> expected, from_runs;
      for (uint32_t v = 0; v < handles.size(); ++v)
        if (lod[v] == b / s_count && ((worn[v] >> (b % s_count)) & 1u)) expected.push_back(v);
      const std::vector<uint32_t> entries(
          c->view().bucketEntries().begin() + c->view().bucketOffsets()[b],
          c->view().bucketEntries().begin() + c->view().bucketOffsets()[b + 1]);
      EXPECT_EQ(entries, expected) << "bucket " << b;
      for (uint32_t r = c->view().bucketRunOffsets()[b]; r < c->view().bucketRunOffsets()[b + 1];
           ++r) {
        const RecordRun run = c->view().bucketRuns()[r];
        EXPECT_GT(run.count, 0u);
        for (uint32_t k = 0; k < run.count; ++k) from_runs.push_back(run.first + k);
      }
      EXPECT_EQ(from_runs, expected) << "bucket " << b;
      runs_total += c->view().bucketRunOffsets()[b + 1] - c->view().bucketRunOffsets()[b];
    }
    // Grouped: the body (bit 0, worn by all) is one run per LOD, any sub-mesh at most 8 runs
    // (one per mask with its bit, joined where consecutive).
    if (grouped) {
      for (uint32_t l = 0; l < c->desc().lod_count; ++l)
        EXPECT_LE(c->view().bucketRunOffsets()[l * s_count + 1] -
                      c->view().bucketRunOffsets()[l * s_count],
                  1u);
      EXPECT_LE(runs_total, size_t(c->view().bucketCount()) * 8);
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
      const FrameSample got = detail::clipFrameSample(bc, t), want = sampleFrames(bc, t);
      ASSERT_EQ(got.frame, want.frame) << bc.name << " t " << t;
      ASSERT_EQ(got.next_frame, want.next_frame) << bc.name << " t " << t;
      ASSERT_EQ(got.fraction, want.fraction) << bc.name << " t " << t;
    }
  }
  EXPECT_GT(stepped, 0u) << "the embedded character has a clip with STEP keys";
}

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
  EXPECT_EQ(crowd.view().stats().visible, 1u);
  EXPECT_EQ(crowd.view().stats().culled_distance, 3u);
  for (const InstanceRecord& r : crowd.view().records())
    for (const auto& row : r.world_rows)
      for (float v : row) EXPECT_TRUE(std::isfinite(v));
  const CullParams p = CrowdExport::cullParams(crowd.view(), camera);
  cull::Selection sel;
  const glm::vec3 c(0.0f, 1.0f, 0.0f);
  EXPECT_FALSE(cull::select(glm::vec3(0.0f, 0.0f, -std::numeric_limits<float>::infinity()),
                            glm::quat(1, 0, 0, 0), 1.0f, c, 1.0f, c, 1.0f, p, &sel));
  EXPECT_TRUE(sel.culled_by_distance);
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
