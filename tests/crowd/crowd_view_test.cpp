// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdView: a crowd advanced once per frame and selected by several cameras gives each view
// exactly what a single-view crowd at that camera gives (1, 2 and 7 threads; crossfades,
// overlays, root motion, events, motion vectors, instances added, removed and teleported), in any
// order of the views, with views added and removed mid-run; the per-view LOD rules; attachment.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "crowd/crowd_test_helpers.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/crowd_view.h"
#include "si/crowd/parallel_for.h"

namespace si {
namespace {

using test::movingCharacter;
using test::movingPalette;
using test::testCamera;

// Everything a selection hands out, for comparison.
struct Selection {
  std::vector<uint8_t> records, layers, previous, previous_layers;
  std::vector<uint32_t> handles, previous_index, offsets, entries, run_offsets, runs;
  std::vector<uint32_t> stats;
};

template <typename T>
std::vector<uint8_t> bytesOf(Span<const T> s) {
  std::vector<uint8_t> out(s.size_bytes());
  if (!out.empty()) std::memcpy(out.data(), s.data(), out.size());
  return out;
}

// `v` is a CrowdManager (its own view) or a CrowdView.
Selection selectionOf(const CrowdView& v) {
  Selection s;
  s.records = bytesOf(v.records());
  s.layers = bytesOf(v.layerRecords());
  s.previous = bytesOf(v.previousRecords());
  s.previous_layers = bytesOf(v.previousLayerRecords());
  for (const InstanceHandle& h : v.visibleHandles()) s.handles.push_back(h.id);
  s.previous_index.assign(v.previousRecordIndices().begin(), v.previousRecordIndices().end());
  s.offsets = v.bucketOffsets();
  s.entries = v.bucketEntries();
  s.run_offsets = v.bucketRunOffsets();
  for (const RecordRun& r : v.bucketRuns()) s.runs.insert(s.runs.end(), {r.first, r.count});
  const CrowdFrameStats& st = v.stats();
  s.stats = {st.instances, st.visible, st.culled_frustum, st.culled_distance, st.bucket_entries};
  s.stats.insert(s.stats.end(), st.per_lod, st.per_lod + 8);
  return s;
}

void expectSame(const Selection& a, const Selection& b, const std::string& what) {
  EXPECT_EQ(a.stats, b.stats) << what;
  EXPECT_EQ(a.records, b.records) << what;
  EXPECT_EQ(a.layers, b.layers) << what;
  EXPECT_EQ(a.previous, b.previous) << what;
  EXPECT_EQ(a.previous_layers, b.previous_layers) << what;
  EXPECT_EQ(a.handles, b.handles) << what;
  EXPECT_EQ(a.previous_index, b.previous_index) << what;
  EXPECT_EQ(a.offsets, b.offsets) << what;
  EXPECT_EQ(a.entries, b.entries) << what;
  EXPECT_EQ(a.run_offsets, b.run_offsets) << what;
  EXPECT_EQ(a.runs, b.runs) << what;
}

std::vector<uint32_t> eventsOf(const CrowdManager& c) {
  std::vector<uint32_t> out;
  for (const AnimationEvent& e : c.events()) out.insert(out.end(), {e.instance.id, e.marker, e.count});
  return out;
}

// A crowd of `n` instances around and behind the cameras, playing the moving character's clips:
// a quarter crossfading, every fifth with root motion, every seventh an overlay on the right
// arm, markers on every clip. The same arguments give the same crowd.
struct World {
  CrowdManager crowd;
  std::vector<InstanceHandle> handles;
};

void makeWorld(World* w, uint32_t n, uint32_t threads) {
  CrowdDesc d;
  d.palette = &movingPalette();
  d.sub_mesh_count = uint32_t(movingCharacter().mesh.sub_meshes.size());
  d.lod_count = uint32_t(movingCharacter().mesh.maxLodCount());
  d.previous_records = true;
  d.worker_threads = threads;
  ASSERT_TRUE(w->crowd.init(d).isOk());
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(movingCharacter().skeleton, movingPalette(), "right arm",
                             {"r_clavicle"}, &arm).isOk());
  uint32_t mask = 0;
  ASSERT_TRUE(w->crowd.addLayerMask(arm, &mask).isOk());
  const uint32_t clips = uint32_t(movingPalette().clips.size());
  for (uint32_t c = 0; c < clips; ++c)
    ASSERT_TRUE(w->crowd.addClipMarker(c, movingPalette().clips[c].duration_seconds * 0.5, "mid").isOk());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (uint32_t i = 0; i < n; ++i) {
    InstanceDesc one;
    one.position = {u(rng) * 300.0 - 150.0, 0.0, u(rng) * 300.0 - 80.0};
    const double a = u(rng) * 6.283185307179586;
    one.rotation = glm::quat(float(std::cos(a / 2)), 0.0f, float(std::sin(a / 2)), 0.0f);
    one.scale = float(0.5 + u(rng));
    one.variation_mask = uint32_t(rng()) | 1u;
    one.clip = uint32_t(rng() % clips);
    one.time_seconds = u(rng) * 2.0;
    one.speed = float(0.5 + u(rng));
    one.root_motion = i % 5 == 0;
    InstanceHandle h;
    ASSERT_TRUE(w->crowd.add(one, &h).isOk());
    if (i % 4 == 0) {
      ASSERT_TRUE(w->crowd.crossfade(h, uint32_t(rng() % clips), 0.1 + u(rng)).isOk());
    }
    if (i % 7 == 0) {
      ASSERT_TRUE(w->crowd.playOverlay(h, uint32_t(rng() % clips), mask, 0.7f, 0.3).isOk());
    }
    w->handles.push_back(h);
  }
}

// What every crowd of a run does between frames: remove one, teleport one, add one.
void editWorld(World* w, int frame) {
  const size_t k = size_t(frame) * 101 % w->handles.size();
  ASSERT_TRUE(w->crowd.remove(w->handles[k]).isOk());
  w->handles.erase(w->handles.begin() + long(k));
  ASSERT_TRUE(w->crowd.setTransform(w->handles[k / 2], {1.0, 0.0, 5.0 + frame}, glm::quat(1, 0, 0, 0), 1.0f).isOk());
  InstanceDesc one;
  one.position = {2.0 * frame, 0.0, 10.0};
  one.clip = uint32_t(frame) % uint32_t(movingPalette().clips.size());
  InstanceHandle h;
  ASSERT_TRUE(w->crowd.add(one, &h).isOk());
  w->handles.push_back(h);
}

// The main camera and a shadow-like one high above, looking down over the crowd.
Camera mainCamera(int frame) { return testCamera({frame * 8.0, 2.0 + frame * 6.0, -30.0}, {0, 0, 100}); }
Camera topCamera(int frame) { return testCamera({-frame * 5.0, 120.0, 20.0}, {0.0, 0.0, 60.0 + frame}); }

TEST(CrowdView, EachViewSelectsWhatASingleViewCrowdAtItsCameraSelects) {
  WorkerPool seven(7);
  const ParallelFor on_seven = [&](uint32_t n, const ParallelTask& t) { seven.run(n, t); };
  const uint32_t n = 9000;  // 3 tasks, the last one partial.
  for (uint32_t threads : {1u, 2u, 7u}) {
    SCOPED_TRACE(testing::Message() << threads << " threads");
    World both, main_only, top_only;
    makeWorld(&both, n, threads);
    makeWorld(&main_only, n, threads);
    makeWorld(&top_only, n, threads);
    CrowdView main_view, top_view;
    ASSERT_TRUE(main_view.init(both.crowd, CrowdViewDesc{0, 0.0f, 0.0f, true}).isOk());
    ASSERT_TRUE(top_view.init(both.crowd, CrowdViewDesc{0, 0.0f, 0.0f, true}).isOk());
    size_t events = 0, top_visible = 0;
    for (int frame = 0; frame < 6; ++frame) {
      const double dt = 0.25;
      if (threads == 7) {  // An engine's job system.
        ASSERT_TRUE(both.crowd.advance(dt, on_seven).isOk());
      } else {
        ASSERT_TRUE(both.crowd.advance(dt).isOk());
      }
      if (frame % 2 == 0) {  // Views in either order.
        ASSERT_TRUE(main_view.select(mainCamera(frame)).isOk());
        ASSERT_TRUE(top_view.select(topCamera(frame)).isOk());
      } else {
        ASSERT_TRUE(top_view.select(topCamera(frame)).isOk());
        ASSERT_TRUE(main_view.select(mainCamera(frame)).isOk());
      }
      ASSERT_TRUE(main_only.crowd.update(dt, mainCamera(frame)).isOk());
      ASSERT_TRUE(top_only.crowd.update(dt, topCamera(frame)).isOk());
      const std::string at = "frame " + std::to_string(frame);
      expectSame(selectionOf(main_only.crowd.view()), selectionOf(main_view), "main view, " + at);
      expectSame(selectionOf(top_only.crowd.view()), selectionOf(top_view), "top view, " + at);
      // Events once per frame, not per view.
      EXPECT_EQ(eventsOf(main_only.crowd), eventsOf(both.crowd)) << at;
      events += both.crowd.events().size();
      top_visible += top_view.stats().visible;
      for (InstanceHandle h : {both.handles[0], both.handles[1]}) {
        uint32_t a = 9, b = 9;
        ASSERT_TRUE(main_view.lodOf(h, &a).isOk());
        ASSERT_TRUE(main_only.crowd.view().lodOf(h, &b).isOk());
        EXPECT_EQ(a, b) << at;
      }
      editWorld(&both, frame);
      editWorld(&main_only, frame);
      editWorld(&top_only, frame);
    }
    // The run exercised what it claims to.
    EXPECT_GT(events, 0u);
    EXPECT_GT(top_visible, 0u);
    EXPECT_NE(selectionOf(main_view).records, selectionOf(top_view).records);
  }
}

// Views of one crowd selected on several threads at once (shadow cascades selected in
// parallel, as engines do): each selects byte for byte what it selects on one thread, frame
// after frame, while the crowd's workers run one view's section and the other views run their
// own on their threads. ThreadSanitizer runs this file too (the tsan.crowd_views test).
TEST(CrowdView, ViewsSelectedOnSeveralThreadsAtOnceSelectWhatTheySelectAlone) {
  World w;
  makeWorld(&w, 20000, 4);  // Five chunks: the crowd's workers take part.
  constexpr int kViews = 4;
  CrowdView alone[kViews], together[kViews];
  CrowdViewDesc vd;
  vd.previous_records = true;
  for (int k = 0; k < kViews; ++k) {
    ASSERT_TRUE(alone[k].init(w.crowd, vd).isOk());
    ASSERT_TRUE(together[k].init(w.crowd, vd).isOk());
  }
  const auto cascade = [](int k, int frame) {
    return testCamera({k * 20.0 - 30.0 + frame, 60.0 + 10.0 * k, -20.0}, {k * 10.0, 0.0, 80.0});
  };
  for (int frame = 0; frame < 4; ++frame) {
    ASSERT_TRUE(w.crowd.update(1.0 / 30.0, mainCamera(frame)).isOk());
    for (int k = 0; k < kViews; ++k) ASSERT_TRUE(alone[k].select(cascade(k, frame)).isOk());
    Status results[kViews];
    std::vector<std::thread> threads;
    for (int k = 0; k < kViews; ++k)
      threads.emplace_back([&, k] { results[k] = together[k].select(cascade(k, frame)); });
    for (std::thread& t : threads) t.join();
    for (int k = 0; k < kViews; ++k) {
      ASSERT_TRUE(results[k].isOk()) << results[k].toString();
      EXPECT_GT(alone[k].stats().visible, 100u);
      expectSame(selectionOf(alone[k]), selectionOf(together[k]),
                 "view " + std::to_string(k) + " frame " + std::to_string(frame));
    }
    editWorld(&w, frame);
  }
}

TEST(CrowdView, AViewAddedOrRemovedMidRunChangesNothingForTheOthers) {
  World both, alone;
  makeWorld(&both, 5000, 1);
  makeWorld(&alone, 5000, 1);
  CrowdView main_view;
  ASSERT_TRUE(main_view.init(both.crowd, CrowdViewDesc{0, 0.0f, 0.0f, true}).isOk());
  auto extra = std::make_unique<CrowdView>();
  for (int frame = 0; frame < 6; ++frame) {
    ASSERT_TRUE(both.crowd.advance(0.2).isOk());
    if (frame == 2) {
      ASSERT_TRUE(extra->init(both.crowd, CrowdViewDesc{1, 0.5f, -1.0f, true}).isOk());
    }
    if (frame >= 2 && extra) {
      ASSERT_TRUE(extra->select(topCamera(frame)).isOk());
    }
    if (frame == 4) extra.reset();  // Its lane freed mid-run.
    ASSERT_TRUE(main_view.select(mainCamera(frame)).isOk());
    ASSERT_TRUE(alone.crowd.update(0.2, mainCamera(frame)).isOk());
    expectSame(selectionOf(alone.crowd.view()), selectionOf(main_view),
               "frame " + std::to_string(frame));
    editWorld(&both, frame);
    editWorld(&alone, frame);
  }
  // A view added after the removal reuses the lane, starting afresh.
  CrowdView again;
  ASSERT_TRUE(again.init(both.crowd).isOk());
  ASSERT_TRUE(again.select(mainCamera(0)).isOk());
  EXPECT_TRUE(again.previousRecords().empty());
}

// The per-view rules: LODs of a biased view are the unbiased view's plus the bias (clamped); a
// distance scale equals the crowd's lines scaled; a negative far line culls by frustum only.
TEST(CrowdView, TheViewsOwnLodRules) {
  World w, scaled;
  makeWorld(&w, 4000, 1);
  makeWorld(&scaled, 4000, 1);
  const uint32_t lods = w.crowd.desc().lod_count;
  ASSERT_GE(lods, 3u);
  std::vector<float> half;
  for (float line : w.crowd.desc().lod_distances_radii) half.push_back(line * 0.5f);
  ASSERT_TRUE(scaled.crowd.setLodDistances(half).isOk());
  CrowdView plain, biased, near_lods, no_far;
  ASSERT_TRUE(plain.init(w.crowd).isOk());
  ASSERT_TRUE(biased.init(w.crowd, CrowdViewDesc{1, 0.0f, 0.0f, false}).isOk());
  ASSERT_TRUE(near_lods.init(w.crowd, CrowdViewDesc{0, 0.5f, 0.0f, true}).isOk());
  ASSERT_TRUE(no_far.init(w.crowd, CrowdViewDesc{0, 0.0f, -1.0f, false}).isOk());
  for (int frame = 0; frame < 3; ++frame) {
    const Camera cam = mainCamera(frame);
    ASSERT_TRUE(w.crowd.advance(0.1).isOk());
    for (CrowdView* v : {&plain, &biased, &near_lods, &no_far}) ASSERT_TRUE(v->select(cam).isOk());
    ASSERT_TRUE(scaled.crowd.update(0.1, cam).isOk());
    expectSame(selectionOf(scaled.crowd.view()), selectionOf(near_lods), "distance scale 0.5");
    EXPECT_EQ(plain.stats().visible, biased.stats().visible);
    uint32_t moved = 0;
    for (InstanceHandle h : plain.visibleHandles()) {
      uint32_t a = 0, b = 0;
      ASSERT_TRUE(plain.lodOf(h, &a).isOk());
      ASSERT_TRUE(biased.lodOf(h, &b).isOk());
      EXPECT_EQ(std::min(a + 1, lods - 1), b);
      moved += a + 1 < lods;
    }
    EXPECT_GT(moved, 0u);
    EXPECT_EQ(biased.stats().per_lod[0], 0u);
    EXPECT_GT(plain.stats().culled_distance, 0u);
    EXPECT_EQ(no_far.stats().culled_distance, 0u);
    EXPECT_EQ(no_far.stats().visible, plain.stats().visible + plain.stats().culled_distance -
                                          (no_far.stats().culled_frustum - plain.stats().culled_frustum));
  }
}

// What GPU-driven culling reads of a view: its identity (new at every init, unique across views
// and crowds), its cull parameters (the crowd's with its rules applied, as select() uses them)
// and its LODs before the bias (what select() left), in CrowdExport::state()'s dense order.
TEST(CrowdView, WhatTheGpuReadsOfAView) {
  World w, other;
  makeWorld(&w, 2000, 1);
  makeWorld(&other, 10, 1);
  CrowdView plain, shadow;
  EXPECT_EQ(plain.identity(), 0u);
  ASSERT_TRUE(plain.init(w.crowd).isOk());
  ASSERT_TRUE(shadow.init(w.crowd, CrowdViewDesc{2, 0.5f, -1.0f, false}).isOk());
  const uint64_t ids[] = {plain.identity(), shadow.identity(), w.crowd.view().identity(),
                          other.crowd.view().identity()};
  for (size_t a = 0; a < 4; ++a) {
    EXPECT_NE(ids[a], 0u);
    for (size_t b = a + 1; b < 4; ++b) EXPECT_NE(ids[a], ids[b]) << a << " " << b;
  }
  const Camera cam = mainCamera(1);
  const CullParams crowd_params = CrowdExport::cullParams(w.crowd.view(), cam),
                   own = CrowdExport::cullParams(plain, cam),
                   rules = CrowdExport::cullParams(shadow, cam);
  EXPECT_EQ(own.lod_bias, 0u);
  EXPECT_EQ(own.max_distance_radii, crowd_params.max_distance_radii);
  EXPECT_EQ(rules.lod_bias, 2u);
  EXPECT_EQ(rules.max_distance_radii, -1.0f);
  for (uint32_t l = 0; l + 1 < crowd_params.lod_count; ++l) {
    EXPECT_EQ(own.lod_lines[l], crowd_params.lod_lines[l]);
    EXPECT_EQ(rules.lod_lines[l], crowd_params.lod_lines[l] * 0.5f);
  }
  ASSERT_TRUE(w.crowd.advance(0.1).isOk());
  ASSERT_TRUE(plain.select(cam).isOk());
  ASSERT_TRUE(shadow.select(cam).isOk());
  std::vector<GpuInstanceState> state;
  std::vector<InstanceHandle> dense;
  CrowdExport(w.crowd).state(&state, &dense);
  std::vector<uint32_t> lods;
  CrowdExport::lods(shadow, &lods);
  ASSERT_EQ(lods.size(), dense.size());
  uint32_t checked = 0, biased = 0;
  for (InstanceHandle h : shadow.visibleHandles()) {
    const size_t i = size_t(std::find(dense.begin(), dense.end(), h) - dense.begin());
    ASSERT_LT(i, dense.size());
    uint32_t drawn = 0;
    ASSERT_TRUE(shadow.lodOf(h, &drawn).isOk());
    EXPECT_EQ(std::min(lods[i] + 2, shadow.lodCount() - 1), drawn);
    ++checked;
    biased += lods[i] + 2 < shadow.lodCount() && lods[i] < drawn;
  }
  EXPECT_GT(checked, 100u);
  EXPECT_GT(biased, 0u) << "some LODs are below the drawn ones";
  // A range exports its slice of the whole; past the crowd, nothing.
  std::vector<uint32_t> slice(40, 99u);
  const DenseRange last{uint32_t(lods.size()) - 40, 40}, past{uint32_t(lods.size()) - 39, 40};
  CrowdExport::lods(shadow, Span<const DenseRange>(&last, 1), slice.data());
  EXPECT_TRUE(std::equal(slice.begin(), slice.end(), lods.end() - 40));
  std::fill(slice.begin(), slice.end(), 99u);
  CrowdExport::lods(shadow, Span<const DenseRange>(&past, 1), slice.data());
  EXPECT_EQ(std::count(slice.begin(), slice.end(), 99u), 40);
  // The crowd's own view exports the LODs CrowdExport::state() carries.
  CrowdExport::lods(w.crowd.view(), &lods);
  for (size_t i = 0; i < state.size(); ++i) EXPECT_EQ(lods[i], state[i].lod);
  // Re-init: a new identity, LODs back to 0; detached: nothing.
  const uint64_t before = shadow.identity();
  ASSERT_TRUE(shadow.init(w.crowd).isOk());
  EXPECT_NE(shadow.identity(), before);
  CrowdExport::lods(shadow, &lods);
  EXPECT_EQ(std::count(lods.begin(), lods.end(), 0u), std::ptrdiff_t(lods.size()));
  CrowdView detached;
  CrowdExport::lods(detached, &lods);
  EXPECT_TRUE(lods.empty());
  EXPECT_EQ(CrowdExport::cullParams(detached, cam).lod_bias, 0u);
}

TEST(CrowdView, AttachmentFollowsTheCrowd) {
  CrowdView view;
  EXPECT_FALSE(view.attached());
  EXPECT_EQ(view.crowd(), nullptr);
  Status s = view.select(mainCamera(0));
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("not attached"), std::string::npos) << s.message();
  CrowdManager never_initialized;
  s = view.init(never_initialized);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("init() first"), std::string::npos) << s.message();

  auto w = std::make_unique<World>();
  makeWorld(w.get(), 100, 1);
  EXPECT_EQ(view.init(w->crowd, CrowdViewDesc{8, 0.0f, 0.0f, false}).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(view.init(w->crowd, CrowdViewDesc{0, -1.0f, 0.0f, false}).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(view.init(w->crowd, CrowdViewDesc{0, 0.0f, NAN, false}).code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(view.attached());
  ASSERT_TRUE(view.init(w->crowd).isOk());
  EXPECT_EQ(view.crowd(), &w->crowd);
  ASSERT_TRUE(w->crowd.advance(0.1).isOk());
  ASSERT_TRUE(view.select(mainCamera(0)).isOk());
  const uint32_t visible = view.stats().visible;
  EXPECT_GT(visible, 0u);

  // A moved crowd keeps its views; a moved view keeps its crowd.
  CrowdManager moved(std::move(w->crowd));
  EXPECT_EQ(view.crowd(), &moved);
  CrowdView other(std::move(view));
  EXPECT_TRUE(other.attached());
  ASSERT_TRUE(other.select(mainCamera(0)).isOk());
  EXPECT_EQ(other.stats().visible, visible);

  // A crowd init() again or destroyed detaches its views, which keep their last selection.
  ASSERT_TRUE(moved.init(moved.desc()).isOk());
  EXPECT_FALSE(other.attached());
  EXPECT_EQ(other.stats().visible, visible);
  EXPECT_EQ(other.select(mainCamera(0)).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(other.init(moved).isOk());
  { CrowdManager gone(std::move(moved)); }
  EXPECT_FALSE(other.attached());
  uint32_t lod = 0;
  EXPECT_EQ(other.lodOf(InstanceHandle(), &lod).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace si
