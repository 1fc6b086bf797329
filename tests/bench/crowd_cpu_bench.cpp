// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The full per-frame CPU path of the crowd: update (time, LOD, cull, bucket, records) plus
// batching (records copied into uniform-block batches, or zero-copy spans), on 1 to 16 threads;
// moving blend parameters, the GPU-driven path's share of churn (live poses:
// live_pose_bench.cpp, in the same binary).
// Items are instances: items_per_second^-1 is the wall time per instance. Not part of ctest.
// Run: build/release/tests/bench/si_crowd_cpu_bench --benchmark_filter='threads:(1|2)/'
// (more threads than cores only measures oversubscription).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include <glm/gtc/quaternion.hpp>

#include "crowd_bench_fixtures.h"
#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

namespace {

using si::bench::field;
using si::bench::palette;

// The right arm's mask of the plain palette (the overlay of the overlays argument).
const si::LayerMask& armMask() {
  static const si::LayerMask mask = [] {
    si::Character c;
    if (!si::makeDefaultCharacter({}, &c).isOk()) std::abort();
    si::LayerMask m;
    if (!si::buildLayerMask(c.skeleton, palette(), "right arm", {"r_clavicle"}, &m).isOk())
      std::abort();
    return m;
  }();
  return mask;
}

// Arguments: instances; scene (0: a camera at the field's edge looking across it, the demo's
// view; 1: high above, looking down, every character in view); threads (CrowdDesc::
// worker_threads); batching (0: InstanceBatcher::build, records copied per draw; 1: buildSpans,
// no copy); markers (1: a marker at the middle of every clip, so animation events are counted
// for every instance); motion (field()'s: compare 1 and 2 for what root motion costs);
// previous (1: CrowdDesc::previous_records, for motion vectors); overlays (1: every instance
// waves its right arm over its clip, and batching writes the layer records too). Two frames run
// before timing (the buffers reach their size).
void crowdFrame(benchmark::State& state) {
  const int64_t count = state.range(0);
  const bool all_visible = state.range(1) != 0;
  const uint32_t threads = uint32_t(state.range(2));
  const bool spans = state.range(3) != 0;
  const double side = std::ceil(std::sqrt(double(count))) * 1.5;
  si::Camera camera;
  std::unique_ptr<si::CrowdManager> crowd;
  if (!all_visible) {
    camera = si::Camera::lookAt({side / 2, 8.0, -10.0}, {side / 2, 0.0, side / 2},
                                glm::vec3(0, 1, 0), 1.0f, 16.0f / 9.0f, 0.1f, 10000.0f);
    crowd = field(count, 0.0f, threads, state.range(5), state.range(6) != 0);
  } else {
    // High above, every character in view and none distance-culled.
    camera = si::Camera::lookAt({side / 2, side * 1.2, side / 2 + 1.0}, {side / 2, 0.0, side / 2},
                                glm::vec3(0, 1, 0), 1.2f, 1.0f, 0.1f, 100000.0f);
    crowd = field(count, -1.0f, threads, state.range(5), state.range(6) != 0);
  }
  if (state.range(4) != 0)
    for (uint32_t c = 0; c < crowd->desc().palette->clips.size(); ++c)
      if (!crowd->addClipMarker(c, crowd->desc().palette->clips[c].duration_seconds * 0.5,
                                "half").isOk())
        std::abort();
  const bool overlays = state.range(7) != 0;
  if (overlays) {
    uint32_t mask = 0;
    std::vector<si::InstanceHandle> handles;
    std::vector<si::GpuInstanceState> states;
    si::CrowdExport(*crowd).state(&states, &handles);
    const uint32_t wave = uint32_t(crowd->desc().palette->findClip("wave"));
    if (!crowd->addLayerMask(armMask(), &mask).isOk()) std::abort();
    for (size_t i = 0; i < handles.size(); ++i)
      if (!crowd->playOverlay(handles[i], wave, mask, 1.0f, 0.0, 0.37 * double(i % 7)).isOk())
        std::abort();
  }
  si::InstanceBatcher batcher;
  if (!batcher.init({65536, 256, 0}).isOk()) std::abort();
  std::vector<uint8_t> buffer, layers;
  std::vector<si::DrawBatch> draws;
  std::vector<si::RecordSpanDraw> span_draws;
  const auto frame = [&] {
    if (!crowd->update(1.0 / 60.0, camera).isOk()) std::abort();
    if (spans) {
      if (!batcher.buildSpans(crowd->view(), &span_draws).isOk()) std::abort();
      benchmark::DoNotOptimize(span_draws.data());
      return;
    }
    const size_t need = batcher.recordBufferBound(crowd->view());
    if (buffer.size() < need) buffer.resize(need);
    if (!batcher.build(crowd->view(), buffer, &draws).isOk()) std::abort();
    benchmark::DoNotOptimize(buffer.data());
    if (!overlays) return;
    const size_t layer_need = batcher.layerBufferBound(crowd->view());
    if (layers.size() < layer_need) layers.resize(layer_need);
    if (!batcher.buildLayers(crowd->view(), layers).isOk()) std::abort();
    benchmark::DoNotOptimize(layers.data());
  };
  frame();
  frame();  // Two: previous_records swaps two record buffers, both then at their size.
  for (auto _ : state) frame();
  state.SetItemsProcessed(state.iterations() * count);
  state.counters["visible"] = crowd->view().stats().visible;
  state.counters["events"] = double(crowd->events().size());
  state.counters["layer_records"] = double(crowd->view().layerRecords().size());
  state.counters["draws"] = double(spans ? span_draws.size() : draws.size());
  state.counters["ns_per_instance"] =
      benchmark::Counter(double(count), benchmark::Counter::kIsIterationInvariantRate |
                                            benchmark::Counter::kInvert);
}
BENCHMARK(crowdFrame)
    ->ArgsProduct({{10000, 100000, 1000000}, {0, 1}, {1, 2, 4, 8, 16}, {0, 1}, {0}, {0}, {0}, {0}})
    ->Args({100000, 1, 1, 1, 1, 0, 0, 0})
    ->Args({1000000, 0, 1, 1, 1, 0, 0, 0})
    ->ArgsProduct({{100000, 1000000}, {0, 1}, {1, 8}, {1}, {0}, {1, 2}, {0}, {0}})
    ->ArgsProduct({{100000, 1000000}, {0, 1}, {1}, {1}, {0}, {0}, {1}, {0}})
    ->ArgsProduct({{100000, 1000000}, {0, 1}, {1, 8}, {0}, {0}, {0}, {0}, {1}})
    ->ArgsProduct({{100000}, {1}, {1}, {1}, {0}, {0, 3, 4, 5}, {0}, {0}})
    ->ArgNames({"instances", "all_visible", "threads", "spans", "markers", "motion", "previous",
                "overlays"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Moving every instance's blend parameter once (CrowdManager::setBlendParameter, what a game
// does each frame from its characters' speeds): a field of `instances` all blending the walk
// and the run on a full-body mask, each call re-anchoring both clips at the phase reached.
// ns_per_instance is one call's cost.
void moveBlends(benchmark::State& state) {
  const int64_t count = state.range(0);
  auto crowd = field(count, -1.0f, 1, 0, false);
  si::Character c;
  if (!si::makeDefaultCharacter({}, &c).isOk()) std::abort();
  si::LayerMask body;
  uint32_t mask = 0, space = 0;
  if (!si::buildFullBodyMask(c.skeleton, palette(), "body", &body).isOk() ||
      !crowd->addLayerMask(body, &mask).isOk() ||
      !crowd
           ->addBlendSpace(
               {"locomotion",
                {uint32_t(palette().findClip("walk")), uint32_t(palette().findClip("run"))},
                {0.0f, 1.0f},
                mask},
               &space)
           .isOk())
    std::abort();
  std::vector<si::InstanceHandle> handles;
  std::vector<si::GpuInstanceState> states;
  si::CrowdExport(*crowd).state(&states, &handles);
  for (size_t i = 0; i < handles.size(); ++i)
    if (!crowd->playBlend(handles[i], space, float(i % 11) / 10.0f, 0.0).isOk()) std::abort();
  float shift = 0.0f;
  for (auto _ : state) {
    shift = shift > 0.5f ? 0.0f : shift + 0.01f;
    for (size_t i = 0; i < handles.size(); ++i)
      if (!crowd->setBlendParameter(handles[i], float(i % 11) / 20.0f + shift).isOk()) std::abort();
  }
  state.SetItemsProcessed(state.iterations() * count);
  state.counters["ns_per_instance"] = benchmark::Counter(
      double(count), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(moveBlends)
    ->Arg(10000)
    ->Arg(100000)
    ->ArgName("instances")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The GPU-driven path's CPU share of churn, what drawCrowdGpuCulled does before its GL calls
// (src/gl/paths/gpu_state_upload.cpp; docs/performance.md, "Several crowds of one character,
// churn and GPU memory"): each iteration removes `per_mille` / 1000 of a field of `instances`
// at random and adds as many (the application's calls, not timed), advances the clock, then
// finds what changed since the last iteration (changedSince), exports the changed runs' state
// and handles (CrowdExport::state) and, for each of `views` views, their LODs where other instances
// sit now (CrowdExport::lods of the placed runs), on a crowd of `threads` worker threads (0:
// the default, the hardware's threads up to 16).
// ns_per_change: per instance changed; find_ms, export_ms and lods_ms: each part's wall time per
// iteration.
void churnExport(benchmark::State& state) {
  const int64_t count = state.range(0);
  const int64_t churn = count * state.range(1) / 1000;
  const int64_t view_count = state.range(2);
  auto crowd = field(count, -1.0f, uint32_t(state.range(3)), 0, false);
  std::vector<std::unique_ptr<si::CrowdView>> views;
  for (int64_t v = 0; v < view_count; ++v) {
    views.push_back(std::make_unique<si::CrowdView>());
    if (!views.back()->init(*crowd).isOk()) std::abort();
  }
  std::vector<si::InstanceHandle> handles;
  std::vector<si::GpuInstanceState> all;
  si::CrowdExport(*crowd).state(&all, &handles);
  uint64_t version = si::CrowdExport(*crowd).stateVersion(), seed = 12345;
  const auto next = [&seed] {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return seed >> 33;
  };
  std::vector<si::DenseRange> changed, placed;
  std::vector<si::GpuInstanceState> states;
  std::vector<si::InstanceHandle> changed_handles;
  std::vector<uint32_t> lods;
  uint64_t changes = 0;
  double parts[4] = {0.0, 0.0, 0.0, 0.0};  // Find, export, LODs, churn: ms summed.
  for (auto _ : state) {
    state.PauseTiming();
    const auto c0 = std::chrono::steady_clock::now();
    for (int64_t k = 0; k < churn; ++k) {
      const size_t at = size_t(next() % handles.size());
      si::InstanceDesc d;
      if (!crowd->get(handles[at], &d).isOk() || !crowd->remove(handles[at]).isOk()) std::abort();
      if (!crowd->add(d, &handles[at]).isOk()) std::abort();
    }
    parts[3] +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - c0).count();
    if (!crowd->advance(1.0 / 60.0).isOk()) std::abort();
    state.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    si::CrowdExport(*crowd).changedSince(version, &changed, &placed);
    const auto t1 = std::chrono::steady_clock::now();
    size_t total = 0;
    for (const si::DenseRange& c : changed) total += c.count;
    states.resize(total);
    changed_handles.resize(total);
    si::CrowdExport(*crowd).state(changed, states.data(), changed_handles.data());
    const auto t2 = std::chrono::steady_clock::now();
    for (const auto& v : views) {
      size_t placed_total = 0;
      for (const si::DenseRange& c : placed) placed_total += c.count;
      lods.assign(placed_total, 0u);
      si::CrowdExport::lods(*v, placed, lods.data());
    }
    benchmark::DoNotOptimize(states.data());
    benchmark::DoNotOptimize(lods.data());
    const auto t3 = std::chrono::steady_clock::now();
    parts[0] += std::chrono::duration<double, std::milli>(t1 - t0).count();
    parts[1] += std::chrono::duration<double, std::milli>(t2 - t1).count();
    parts[2] += std::chrono::duration<double, std::milli>(t3 - t2).count();
    version = si::CrowdExport(*crowd).stateVersion();
    changes += total;
  }
  const double iterations = double(std::max<int64_t>(1, int64_t(state.iterations())));
  state.counters["find_ms"] = parts[0] / iterations;
  state.counters["export_ms"] = parts[1] / iterations;
  state.counters["lods_ms"] = parts[2] / iterations;
  state.counters["churn_ms"] = parts[3] / iterations;
  state.counters["changed_per_iteration"] =
      double(changes) / double(std::max<int64_t>(1, int64_t(state.iterations())));
  state.counters["ns_per_change"] = benchmark::Counter(
      double(changes) / double(state.iterations()),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(churnExport)
    ->ArgsProduct({{1000000}, {10, 1}, {0, 4}, {1, 0}})
    ->ArgNames({"instances", "per_mille", "views", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
