#include "si/crowd/crowd_export.h"
// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// What GPU-driven draws upload: CrowdExport::changedSince names exactly the dense indices whose
// exported state changed since a version (setters, play, root motion, add, remove), and those
// holding another instance; the range exports equal the whole exports there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "crowd/change_log.h"
#include "crowd/crowd_test_helpers.h"
#include "crowd/dense_runs.h"
#include "crowd/instance_store.h"

namespace si {
namespace {

// The dense indices a list of ranges covers.
std::vector<uint32_t> indices(const std::vector<DenseRange>& ranges) {
  std::vector<uint32_t> out;
  for (const DenseRange& r : ranges)
    for (uint32_t i = r.first; i < r.first + r.count; ++i) out.push_back(i);
  return out;
}

// Dense index of a handle, from the whole export's handle order.
uint32_t denseOf(const CrowdManager& crowd, InstanceHandle h) {
  std::vector<GpuInstanceState> state;
  std::vector<InstanceHandle> dense;
  CrowdExport(crowd).state(&state, &dense);
  for (uint32_t i = 0; i < dense.size(); ++i)
    if (dense[i] == h) return i;
  ADD_FAILURE() << "handle not found";
  return 0;
}

// A crowd of the moving character (its walk carries root motion).
Status initMovingCrowd(CrowdManager* crowd) {
  CrowdDesc cd = test::defaultCrowdDesc();
  cd.palette = &test::movingPalette();
  return crowd->init(cd);
}

std::vector<InstanceHandle> populate(CrowdManager* crowd, uint32_t n) {
  std::vector<InstanceHandle> handles(n);
  for (uint32_t i = 0; i < n; ++i) {
    InstanceDesc d;
    d.position = glm::dvec3(double(i % 100), 0.0, double(i / 100));
    EXPECT_TRUE(crowd->add(d, &handles[i]).isOk());
  }
  return handles;
}

TEST(StateChanges, EachChangeNamesItsIndexAndNothingElse) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(test::defaultCrowdDesc()).isOk());
  const std::vector<InstanceHandle> h = populate(&crowd, 5000);  // Five stamp chunks.
  std::vector<DenseRange> changed, placed;
  CrowdExport(crowd).changedSince(0, &changed, &placed);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].first, 0u);
  EXPECT_EQ(changed[0].count, 5000u);
  EXPECT_EQ(indices(placed), indices(changed));

  uint64_t since = CrowdExport(crowd).stateVersion();
  CrowdExport(crowd).changedSince(since, &changed, &placed);
  EXPECT_TRUE(changed.empty());
  EXPECT_TRUE(placed.empty());

  // Setters, far apart (their own runs), in several chunks; placed untouched.
  ASSERT_TRUE(crowd.setColor(h[10], glm::u8vec4(1, 2, 3, 255)).isOk());
  ASSERT_TRUE(crowd.setVariationMask(h[2100], 0x3).isOk());
  ASSERT_TRUE(crowd.play(h[4999], 1, 0.5, 1.0f).isOk());
  CrowdExport(crowd).changedSince(since, &changed, &placed);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{10, 2100, 4999}));
  EXPECT_TRUE(placed.empty());
  // Only what changed after a later version.
  const uint64_t later = CrowdExport(crowd).stateVersion();
  ASSERT_TRUE(crowd.setTransform(h[3000], glm::dvec3(1.0), glm::quat(1, 0, 0, 0), 2.0f).isOk());
  CrowdExport(crowd).changedSince(later, &changed, nullptr);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{3000}));

  // Adjacent indices form one run; a gap of one unchanged index parts two (nothing unchanged is
  // exported again).
  since = CrowdExport(crowd).stateVersion();
  ASSERT_TRUE(crowd.crossfade(h[100], 2, 0.3).isOk());
  ASSERT_TRUE(crowd.setCustomLayer(h[101], 3).isOk());
  ASSERT_TRUE(crowd.setCustomLayer(h[103], 3).isOk());
  CrowdExport(crowd).changedSince(since, &changed, nullptr);
  ASSERT_EQ(changed.size(), 2u);
  EXPECT_EQ(changed[0].first, 100u);
  EXPECT_EQ(changed[0].count, 2u);
  EXPECT_EQ(changed[1].first, 103u);
  EXPECT_EQ(changed[1].count, 1u);

  // A removal moves the last instance into the hole: changed and placed there; the count falls.
  since = CrowdExport(crowd).stateVersion();
  const uint32_t hole = denseOf(crowd, h[7]);
  ASSERT_TRUE(crowd.remove(h[7]).isOk());
  CrowdExport(crowd).changedSince(since, &changed, &placed);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{hole}));
  EXPECT_EQ(indices(placed), (std::vector<uint32_t>{hole}));
  EXPECT_EQ(denseOf(crowd, h[4999]), hole);
  // An add is changed and placed at the end.
  since = CrowdExport(crowd).stateVersion();
  InstanceHandle added;
  ASSERT_TRUE(crowd.add(InstanceDesc(), &added).isOk());
  CrowdExport(crowd).changedSince(since, &changed, &placed);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{4999}));
  EXPECT_EQ(indices(placed), (std::vector<uint32_t>{4999}));
  // Removing the last instance changes nothing that remains.
  since = CrowdExport(crowd).stateVersion();
  ASSERT_TRUE(crowd.remove(added).isOk());
  CrowdExport(crowd).changedSince(since, &changed, &placed);
  EXPECT_TRUE(changed.empty());
  EXPECT_TRUE(placed.empty());
  // Neither an update (LODs, crossfade ends) nor the clock changes exported state.
  since = CrowdExport(crowd).stateVersion();
  ASSERT_TRUE(crowd.update(0.5, test::testCamera({0, 2, -10}, {0, 0, 50})).isOk());
  ASSERT_TRUE(crowd.advance(0.5).isOk());
  CrowdExport(crowd).changedSince(since, &changed, &placed);
  EXPECT_TRUE(changed.empty());
}

// Root motion stamps the instances it moves, each frame; the range export equals the whole
// export on every index, and overlays likewise.
TEST(StateChanges, RootMotionStampsWhatMovedAndRangeExportsEqualTheWhole) {
  CrowdManager crowd;
  ASSERT_TRUE(initMovingCrowd(&crowd).isOk());
  const uint32_t walk = uint32_t(test::movingPalette().findClip("walk_forward"));
  std::vector<InstanceHandle> h(3000);
  for (uint32_t i = 0; i < h.size(); ++i) {
    InstanceDesc d;
    d.position = glm::dvec3(double(i), 0.0, 0.0);
    d.clip = walk;
    d.root_motion = i % 1000 == 5;  // Three walkers, in three chunks.
    ASSERT_TRUE(crowd.add(d, &h[i]).isOk());
  }
  uint64_t since = CrowdExport(crowd).stateVersion();
  for (int frame = 0; frame < 3; ++frame) {
    ASSERT_TRUE(crowd.advance(0.1).isOk());
    std::vector<DenseRange> changed, placed;
    CrowdExport(crowd).changedSince(since, &changed, &placed);
    EXPECT_EQ(indices(changed), (std::vector<uint32_t>{5, 1005, 2005})) << frame;
    EXPECT_TRUE(placed.empty());
    since = CrowdExport(crowd).stateVersion();
  }
  ASSERT_TRUE(crowd.advance(0.0).isOk());  // No time, no motion.
  std::vector<DenseRange> changed;
  CrowdExport(crowd).changedSince(since, &changed, nullptr);
  EXPECT_TRUE(changed.empty());

  std::vector<GpuInstanceState> whole;
  std::vector<InstanceHandle> dense;
  CrowdExport(crowd).state(&whole, &dense);
  const DenseRange range{995, 20};
  const Span<const DenseRange> one(&range, 1);
  std::vector<GpuInstanceState> part(range.count);
  std::vector<InstanceHandle> part_handles(range.count);
  CrowdExport(crowd).state(one, part.data(), part_handles.data());
  for (uint32_t k = 0; k < range.count; ++k) {
    EXPECT_EQ(std::memcmp(&part[k], &whole[range.first + k], sizeof(GpuInstanceState)), 0) << k;
    EXPECT_EQ(part_handles[k], dense[range.first + k]);
  }
  // Overlays: playing one stamps its instance; the range export equals the whole.
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(test::movingCharacter().skeleton, test::movingPalette(), "arm",
                             {"r_clavicle"}, &arm).isOk());
  uint32_t mask = 0;
  ASSERT_TRUE(crowd.addLayerMask(arm, &mask).isOk());
  EXPECT_FALSE(CrowdExport(crowd).playsOverlays());
  since = CrowdExport(crowd).stateVersion();
  ASSERT_TRUE(crowd.playOverlay(h[1000], walk, mask, 0.7f, 0.2).isOk());
  EXPECT_TRUE(CrowdExport(crowd).playsOverlays());
  CrowdExport(crowd).changedSince(since, &changed, nullptr);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{1000}));
  std::vector<GpuOverlayState> overlays, part_overlays(range.count);
  CrowdExport(crowd).overlays(&overlays);
  CrowdExport(crowd).overlays(one, part_overlays.data());
  for (uint32_t k = 0; k < range.count; ++k)
    EXPECT_EQ(std::memcmp(&part_overlays[k], &overlays[range.first + k], sizeof(GpuOverlayState)),
              0) << k;
  EXPECT_EQ(part_overlays[1000 - range.first].active, 1u);
  // A run past the end writes nothing, not even the runs before it.
  GpuInstanceState sentinel[2]{};
  sentinel[0].scale = sentinel[1].scale = 7.0f;
  const DenseRange past[2] = {{0, 1}, {2990, 11}};
  CrowdExport(crowd).state(past, sentinel, nullptr);
  EXPECT_EQ(sentinel[0].scale, 7.0f);
  EXPECT_EQ(sentinel[1].scale, 7.0f);
}

// A held clock (dt 0) is held exactly, even where the clock's compensated sum carries half an
// ulp: the steps below leave 1.019 with a compensation of -2^-53, which a dt of 0 added through
// the sum would round one ulp up (so walkers moved with no version to name it: the clang fuzz
// build's crowd-api-changed-since-clang-1.bin).
TEST(StateChanges, AHeldClockStaysBitwiseAndMovesNothing) {
  CrowdManager crowd;
  ASSERT_TRUE(initMovingCrowd(&crowd).isOk());
  InstanceDesc d;
  d.clip = uint32_t(test::movingPalette().findClip("walk_forward"));
  d.root_motion = true;
  InstanceHandle walker;
  ASSERT_TRUE(crowd.add(d, &walker).isOk());
  for (double dt : {0.028, 0.23, 0.177, 0.584}) ASSERT_TRUE(crowd.advance(dt).isOk());
  for (int held = 0; held < 2; ++held) {  // advance(0), then update(0).
    const double clock = crowd.clockSeconds();
    const uint64_t since = CrowdExport(crowd).stateVersion();
    InstanceDesc was, is;
    ASSERT_TRUE(crowd.get(walker, &was).isOk());
    ASSERT_TRUE((held == 0 ? crowd.advance(0.0)
                           : crowd.update(0.0, test::testCamera({0, 2, -10}, {0, 0, 50})))
                    .isOk());
    const double now = crowd.clockSeconds();
    EXPECT_EQ(std::memcmp(&now, &clock, sizeof(now)), 0) << held << ": " << now - clock;
    ASSERT_TRUE(crowd.get(walker, &is).isOk());
    EXPECT_EQ(is.position, was.position) << held;
    std::vector<DenseRange> changed;
    CrowdExport(crowd).changedSince(since, &changed, nullptr);
    EXPECT_TRUE(changed.empty()) << held;
  }
  EXPECT_EQ(crowd.stepCount(), 6u);  // A held step is still a step.
}

// The ranged exports walk their runs in tasks on the crowd's workers past 512 indices, each
// task starting within some run: whatever the threads, every entry is the whole export's.
TEST(StateChanges, RunExportsEqualTheWholeOnAnyNumberOfThreads) {
  for (uint32_t threads : {1u, 3u, 0u}) {
    SCOPED_TRACE(threads);
    CrowdManager crowd;
    CrowdDesc cd = test::defaultCrowdDesc();
    cd.palette = &test::movingPalette();
    cd.worker_threads = threads;
    ASSERT_TRUE(crowd.init(cd).isOk());
    // Past kRunTasks x kRunTaskIndices: the whole run is cut into the most tasks there are.
    const std::vector<InstanceHandle> h = populate(&crowd, 40000);
    LayerMask arm;
    ASSERT_TRUE(buildLayerMask(test::movingCharacter().skeleton, test::movingPalette(), "arm",
                               {"r_clavicle"}, &arm)
                    .isOk());
    uint32_t mask = 0;
    ASSERT_TRUE(crowd.addLayerMask(arm, &mask).isOk());
    for (uint32_t i = 0; i < h.size(); i += 7)
      ASSERT_TRUE(crowd.playOverlay(h[i], 0, mask, 0.25f + float(i % 3) * 0.25f, 0.2).isOk());
    for (uint32_t i = 0; i < h.size(); i += 5)
      ASSERT_TRUE(crowd.setColor(h[i], glm::u8vec4(uint8_t(i), 9, 9, 255)).isOk());
    // LODs by distance from a camera over the field.
    ASSERT_TRUE(crowd.update(0.1, test::testCamera({50, 10, -20}, {50, 0, 100})).isOk());

    // Runs scattered as churn leaves them (some empty), then one run of the whole crowd.
    std::mt19937 rng(threads + 1);
    std::vector<DenseRange> runs;
    for (uint32_t at = 0;;) {
      const DenseRange r{at + uint32_t(rng() % 20), uint32_t(rng() % 7)};
      if (r.first + r.count > h.size()) break;
      runs.push_back(r);
      at = r.first + r.count;
    }
    std::vector<DenseRange> whole_run{{0, uint32_t(h.size())}};
    std::vector<GpuInstanceState> whole;
    std::vector<InstanceHandle> dense;
    std::vector<GpuOverlayState> overlays;
    std::vector<uint32_t> lods;
    CrowdExport(crowd).state(&whole, &dense);
    CrowdExport(crowd).overlays(&overlays);
    CrowdExport::lods(crowd.view(), &lods);
    ASSERT_EQ(lods.size(), h.size());
    ASSERT_NE(*std::min_element(lods.begin(), lods.end()),
              *std::max_element(lods.begin(), lods.end()));
    for (std::vector<DenseRange>* list : {&runs, &whole_run}) {
      const size_t total = indices(*list).size();
      ASSERT_GT(total, 2 * detail::kRunTaskIndices);
      std::vector<GpuInstanceState> part(total);
      std::vector<InstanceHandle> part_handles(total);
      std::vector<GpuOverlayState> part_overlays(total);
      std::vector<uint32_t> part_lods(total, 99u);
      CrowdExport(crowd).state(*list, part.data(), part_handles.data());
      CrowdExport(crowd).overlays(*list, part_overlays.data());
      CrowdExport::lods(crowd.view(), *list, part_lods.data());
      size_t p = 0;
      for (uint32_t i : indices(*list)) {
        ASSERT_EQ(std::memcmp(&part[p], &whole[i], sizeof(GpuInstanceState)), 0) << i;
        ASSERT_EQ(part_handles[p], dense[i]) << i;
        ASSERT_EQ(std::memcmp(&part_overlays[p], &overlays[i], sizeof(GpuOverlayState)), 0) << i;
        ASSERT_EQ(part_lods[p], lods[i]) << i;
        ++p;
      }
    }
  }
}

// An instance's state as the GPU-driven pass reads it at crowd clock `clock`: update()'s LOD
// field and a crossfade past its end (update() ends it; the GPU sees it over) do not count.
GpuInstanceState onGpu(GpuInstanceState g, double clock) {
  g.lod = 0;
  if (g.fading == 0 || !(g.fade_duration > 0.0) || !(clock - g.fade_start < g.fade_duration)) {
    g.fading = 0;
    g.fade_start = g.fade_duration = g.from_start_clock = g.from_start_time = 0.0;
    g.from_clip = g.from_loop = 0;
    g.from_speed = 0.0f;
  }
  return g;
}

// The change log (crowd/change_log.h) answers what scanning the stamps answers: a model of the
// store's stamps (changes, adds and removes as InstanceStore makes them, and unlogged stamps as
// root motion makes them, the log starting over after them) with a small log that drops its
// older half several times; for every version since which the log holds, its runs of changed
// and of re-occupied indices equal the scan's, and it holds for the recent ones; it answers
// (changedSince reads it) only for those, and not where the changes are many.
TEST(StateChanges, TheLogNamesWhatTheStampsName) {
  std::vector<uint64_t> changed_at, placed_at, chunk_changed, chunk_placed;
  detail::ChangeLog log;
  uint64_t version = 1;
  log.restart(version);
  const size_t limit = 64;
  const auto stamp = [&](uint32_t i, bool placed, bool logged) {
    changed_at[i] = version;
    chunk_changed[i / detail::kStampChunk] = version;
    if (placed) {
      placed_at[i] = version;
      chunk_placed[i / detail::kStampChunk] = version;
    }
    if (logged) log.add(version, i, placed, limit);
  };
  const auto push = [&] {
    changed_at.push_back(0);
    placed_at.push_back(0);
    const size_t chunks = (changed_at.size() + detail::kStampChunk - 1) / detail::kStampChunk;
    chunk_changed.resize(std::max(chunk_changed.size(), chunks), 0);
    chunk_placed.resize(std::max(chunk_placed.size(), chunks), 0);
    ++version;
    stamp(uint32_t(changed_at.size() - 1), true, true);
  };
  // Past 4096 indices: the log's bits say which of their 64-index words hold one in words of
  // their own.
  for (int i = 0; i < 5000; ++i) push();
  std::mt19937 rng(20261129);
  size_t compared = 0, scanned = 0, answered = 0;
  uint64_t drops_seen = 0;
  for (int step = 0; step < 2000; ++step) {
    const uint32_t n = uint32_t(changed_at.size());
    const uint32_t kind = uint32_t(rng() % 10);
    const size_t before = log.size();
    if (kind < 5) {  // A setter.
      ++version;
      stamp(uint32_t(rng() % n), false, true);
    } else if (kind < 7) {  // An add.
      push();
    } else if (kind < 9) {  // A remove: the last moves into the hole.
      const uint32_t i = uint32_t(rng() % n), last = n - 1;
      changed_at[i] = changed_at[last];
      placed_at[i] = placed_at[last];
      changed_at.pop_back();
      placed_at.pop_back();
      ++version;
      if (i != last) stamp(i, true, true);
    } else if (rng() % 20 == 0) {  // Root motion: many stamps of one version, unlogged.
      ++version;
      log.restart(version);
      for (int k = 0; k < 50; ++k) stamp(uint32_t(rng() % n), false, false);
    }
    drops_seen += log.size() < before ? 1 : 0;
    for (int q = 0; q < 4; ++q) {
      const uint64_t since = version - std::min<uint64_t>(version, rng() % 200);
      const uint32_t now = uint32_t(changed_at.size());
      std::vector<DenseRange> want_changed, want_placed, got_changed, got_placed;
      detail::scanStamps(changed_at, chunk_changed, since, now, &want_changed);
      detail::scanStamps(placed_at, chunk_placed, since, now, &want_placed);
      answered += log.answers(since, now) ? 1 : 0;  // Held, and few for the indices.
      if (!log.holds(since)) {
        ++scanned;
        EXPECT_FALSE(log.answers(since, now));
        continue;
      }
      log.since(since, now, &got_changed, &got_placed);
      ASSERT_EQ(indices(got_changed), indices(want_changed))
          << "step " << step << " since " << since;
      ASSERT_EQ(indices(got_placed), indices(want_placed)) << "step " << step << " since " << since;
      ASSERT_EQ(got_changed.size(), want_changed.size());  // The same runs, not just indices.
      ASSERT_EQ(got_placed.size(), want_placed.size());
      ++compared;
    }
    ASSERT_TRUE(log.holds(version));  // The latest version always: nothing changed since.
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_GT(scanned, 10u);     // Older than the log: the stamps answer.
  EXPECT_GT(drops_seen, 10u);  // The log dropped its older half.
  EXPECT_GT(answered, 100u);
  // changedSince reads the log for the few changes and scans the stamps for the many.
  detail::ChangeLog few;
  few.restart(0);
  for (uint32_t i = 0; i < 100; ++i) few.add(i + 1, i, false, 1000);
  EXPECT_TRUE(few.answers(0, 100 * uint32_t(detail::ChangeLog::kEntriesPerIndex) + 1));
  EXPECT_FALSE(few.answers(0, 100 * uint32_t(detail::ChangeLog::kEntriesPerIndex)));
  EXPECT_TRUE(few.answers(50, 50 * uint32_t(detail::ChangeLog::kEntriesPerIndex) + 1));
}

// Random sequences of every kind of change, walkers moving by root motion between them: after
// each step, every dense index whose state (or overlay) differs on the GPU from the last check,
// or holds another instance, lies in changedSince's ranges, and every re-occupied one in its
// placed ranges.
TEST(StateChanges, RandomSequencesNameEveryChange) {
  CrowdManager crowd;
  ASSERT_TRUE(initMovingCrowd(&crowd).isOk());
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(test::movingCharacter().skeleton, test::movingPalette(), "arm",
                             {"r_clavicle"}, &arm).isOk());
  uint32_t mask = 0;
  ASSERT_TRUE(crowd.addLayerMask(arm, &mask).isOk());
  const uint32_t clips = uint32_t(test::movingPalette().clips.size());
  std::mt19937 rng(20261126);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<InstanceHandle> live;
  std::vector<GpuInstanceState> was, is;
  std::vector<InstanceHandle> was_handles, is_handles;
  std::vector<GpuOverlayState> was_overlays, is_overlays;
  uint64_t since = CrowdExport(crowd).stateVersion();
  CrowdExport(crowd).state(&was, &was_handles);
  uint32_t checked = 0;
  for (int step = 0; step < 600; ++step) {
    const uint32_t pick = uint32_t(rng() % 12);  // 0, 10 and 11: add.
    const uint32_t kind = live.empty() || pick >= 10 ? 0u : pick;
    const InstanceHandle h = live.empty() ? InstanceHandle{} : live[rng() % live.size()];
    for (int repeat = 0; repeat < 1 + int(rng() % 3); ++repeat) switch (kind) {
      case 0: {
        InstanceDesc d;
        d.position = glm::dvec3(u(rng) * 100.0, 0.0, u(rng) * 100.0);
        d.clip = uint32_t(rng() % clips);
        d.root_motion = rng() % 3 == 0;
        InstanceHandle added;
        ASSERT_TRUE(crowd.add(d, &added).isOk());
        live.push_back(added);
        break;
      }
      case 1:
        if (crowd.remove(h).isOk()) live.erase(std::find(live.begin(), live.end(), h));
        break;
      case 2: (void)crowd.setColor(h, glm::u8vec4(uint8_t(rng()), 9, 9, 255)); break;
      case 3:
        (void)crowd.setTransform(h, glm::dvec3(u(rng), 0.0, u(rng)), glm::quat(1, 0, 0, 0), 1.0f);
        break;
      case 4: (void)crowd.play(h, uint32_t(rng() % clips), u(rng), 1.0f); break;
      case 5: (void)crowd.crossfade(h, uint32_t(rng() % clips), 0.05 + u(rng) * 0.3); break;
      case 6: (void)crowd.setVariationMask(h, uint32_t(rng())); break;
      case 7: (void)crowd.setRootMotion(h, rng() % 2 == 0); break;
      case 8:
        if (rng() % 2) (void)crowd.playOverlay(h, uint32_t(rng() % clips), mask, float(u(rng)), 0.1);
        else (void)crowd.stopOverlay(h, 0.1);
        break;
      default:
        if (rng() % 2) ASSERT_TRUE(crowd.advance(u(rng) * 0.2).isOk());
        else ASSERT_TRUE(crowd.update(u(rng) * 0.2, test::testCamera({0, 2, -10}, {50, 0, 50})).isOk());
        break;
    }
    CrowdExport(crowd).state(&is, &is_handles);
    CrowdExport(crowd).overlays(&is_overlays);
    std::vector<DenseRange> changed, placed;
    CrowdExport(crowd).changedSince(since, &changed, &placed);
    std::vector<uint8_t> covered(is.size(), 0), moved(is.size(), 0);
    for (const DenseRange& r : changed) std::fill(covered.begin() + r.first, covered.begin() + r.first + r.count, 1);
    for (const DenseRange& r : placed) std::fill(moved.begin() + r.first, moved.begin() + r.first + r.count, 1);
    const double clock = crowd.clockSeconds();
    const GpuOverlayState none{};
    for (size_t i = 0; i < is.size(); ++i) {
      const bool other = i >= was.size() || was_handles[i] != is_handles[i];
      if (other) {
        ASSERT_TRUE(moved[i] && covered[i]) << "step " << step << ": index " << i << " not placed";
        continue;
      }
      const GpuInstanceState a = onGpu(was[i], clock), b = onGpu(is[i], clock);
      const GpuOverlayState& oa = i < was_overlays.size() ? was_overlays[i] : none;
      const GpuOverlayState& ob = i < is_overlays.size() ? is_overlays[i] : none;
      if (std::memcmp(&a, &b, sizeof(a)) != 0 || std::memcmp(&oa, &ob, sizeof(oa)) != 0) {
        ASSERT_TRUE(covered[i]) << "step " << step << " kind " << kind << ": index " << i
                                << " changed unnamed";
        ++checked;
      }
    }
    since = CrowdExport(crowd).stateVersion();
    was.swap(is);
    was_handles.swap(is_handles);
    was_overlays.swap(is_overlays);
  }
  EXPECT_GT(checked, 500u);  // Changes were made and named.
  EXPECT_GT(live.size(), 50u);
}

}  // namespace
}  // namespace si
