// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The full per-frame CPU path of the crowd: update (time, LOD, cull, bucket, records) plus
// batching (records copied into uniform-block batches, or zero-copy spans), on 1 to 16 threads;
// moving blend parameters, live poses set, the GPU-driven path's share of churn.
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

#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

namespace {

// The embedded character at 30 Hz; `moving`: with its travelling clips (root motion);
// `automatic`: baked with the default desc instead (automatic rates, frames at the keys where
// that takes fewer: non-uniform frame times, found by a search per instance).
const si::BakedPalette& palette(bool moving = false, bool automatic = false) {
  static const auto bake = [](bool with_moving_clips, bool default_desc) {
    si::DefaultCharacterDesc cd;
    cd.moving_clips = with_moving_clips;
    si::Character c;
    if (!si::makeDefaultCharacter(cd, &c).isOk()) std::abort();
    si::BakeDesc d;
    if (!default_desc) d.rate_mode = si::RateMode::kFixed;
    si::BakedPalette out;
    if (!si::bakePalette(c, d, &out, nullptr).isOk()) std::abort();
    return out;
  };
  static const si::BakedPalette plain = bake(false, false), travelling = bake(true, false);
  static const si::BakedPalette plain_default = bake(false, true);
  return automatic ? plain_default : moving ? travelling : plain;
}

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

// A square field of `count` characters 1.5 m apart, random armour, clips and times;
// `max_distance_radii` as in CrowdDesc (0: the default far line, negative: none). `motion`: 0
// any clip of the plain palette; 1 the travelling clips (walk_forward, walk_turn_left) played
// in place; 2 the same with root motion applied to every instance; 3 any clip of the plain
// character baked with the default desc (compare with 0: what non-uniform frames cost); 4 as 0,
// every instance crossfading into another clip (a 1000 s fade: it never ends while timed); 5 as
// 0 with animation-LOD stepping from LOD 1 (CrowdDesc::animation_lod_start).
std::unique_ptr<si::CrowdManager> field(int64_t count, float max_distance_radii, uint32_t threads,
                                        int64_t motion, bool previous_records,
                                        uint32_t live_poses = 0) {
  auto crowd = std::make_unique<si::CrowdManager>();
  si::CrowdDesc d;
  d.palette = &palette(motion == 1 || motion == 2, motion == 3);
  d.sub_mesh_count = 4;
  d.lod_count = 3;
  d.max_distance_radii = max_distance_radii;
  d.worker_threads = threads;
  d.previous_records = previous_records;
  d.live_pose_capacity = live_poses;
  if (motion == 5) d.animation_lod_start = 1;
  if (!crowd->init(d).isOk()) std::abort();
  const int64_t side = int64_t(std::ceil(std::sqrt(double(count))));
  std::vector<glm::dvec3> positions;
  for (int64_t i = 0; i < count; ++i)
    positions.push_back(glm::dvec3(double(i % side), 0.0, double(i / side)) * 1.5);
  si::RandomCrowdDesc r;
  r.positions = positions;
  r.optional_mask = 0xE;
  const uint32_t travelling[] = {uint32_t(palette(true).findClip("walk_forward")),
                                 uint32_t(palette(true).findClip("walk_turn_left"))};
  if (motion == 1 || motion == 2) r.clips = travelling;
  r.root_motion = motion == 2;
  std::vector<si::InstanceHandle> handles;
  if (!crowd->addRandom(r, &handles).isOk()) std::abort();
  if (motion == 4) {
    const uint32_t clips = uint32_t(d.palette->clips.size());
    for (size_t i = 0; i < handles.size(); ++i)
      if (!crowd->crossfade(handles[i], uint32_t(i % clips), 1000.0, 0.1 * double(i % 13)).isOk())
        std::abort();
  }
  return crowd;
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

// Poses for setLivePose: the stored matrices of clip 0's first 16 frames (repeated when it has
// fewer), one per palette joint each.
std::vector<std::vector<glm::mat4>> clipPoses(const si::BakedPalette& p) {
  std::vector<std::vector<glm::mat4>> poses(16, std::vector<glm::mat4>(p.palette_joints.size()));
  for (uint32_t k = 0; k < poses.size(); ++k)
    for (uint32_t j = 0; j < p.palette_joints.size(); ++j)
      poses[k][j] = si::decodeJoint(p, 0, k % p.clips[0].frame_count, j);
  return poses;
}

// Live poses (CrowdManager::setLivePose; docs/crowd.md, "Live poses"): each iteration advances
// the clock, gives `live` instances of a field of 100,000 (every tenth) a new pose of the
// embedded character's 21 palette joints (a baked frame's matrices, another one each time:
// every live frame written), then selects at the new clock (update(0)), the frame order an
// engine follows. set_ms: the poses' share per iteration; select_ms: the selection's;
// ns_per_pose: one setLivePose call. Compare select_ms with live 0 for what posed instances
// add to the selection.
void livePoses(benchmark::State& state) {
  const int64_t count = 100000, live = state.range(0);
  auto crowd = field(count, -1.0f, 1, 0, false, uint32_t(std::max<int64_t>(live, 1)));
  std::vector<si::InstanceHandle> handles;
  std::vector<si::GpuInstanceState> states;
  si::CrowdExport(*crowd).state(&states, &handles);
  const si::BakedPalette& p = palette();
  const std::vector<std::vector<glm::mat4>> poses = clipPoses(p);
  const si::Camera camera =
      si::Camera::lookAt({237.0, 9.0, -7.0}, {237.0, 0.0, 45.0}, glm::vec3(0, 1, 0), 0.9f,
                         16.0f / 9.0f, 0.2f, 2000.0f);
  double set_ms = 0.0, select_ms = 0.0;
  uint32_t frame = 0;
  for (auto _ : state) {
    if (!crowd->advance(1.0 / 60.0).isOk()) std::abort();
    ++frame;
    const auto t0 = std::chrono::steady_clock::now();
    for (int64_t k = 0; k < live; ++k)
      if (!crowd->setLivePose(handles[size_t(k) * 10], poses[(size_t(k) + frame) % poses.size()])
               .isOk())
        std::abort();
    const auto t1 = std::chrono::steady_clock::now();
    if (!crowd->update(0.0, camera).isOk()) std::abort();
    const auto t2 = std::chrono::steady_clock::now();
    set_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
    select_ms += std::chrono::duration<double, std::milli>(t2 - t1).count();
  }
  const double n = double(state.iterations());
  state.counters["set_ms"] = set_ms / n;
  state.counters["select_ms"] = select_ms / n;
  state.counters["ns_per_pose"] = live > 0 ? set_ms * 1e6 / (n * double(live)) : 0.0;
}
BENCHMARK(livePoses)
    ->Arg(0)
    ->Arg(1000)
    ->Arg(10000)
    ->ArgName("live")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The palette of a chain of `joints` joints, one vertex per joint, one clip bending it: a
// character of any joint count (the repository's assets stop at 21 palette joints).
const si::BakedPalette& chainPalette(uint32_t joints,
                                     si::PaletteFormat format = si::PaletteFormat::kDefault) {
  static std::map<std::pair<uint32_t, si::PaletteFormat>, si::BakedPalette> baked;
  auto it = baked.find({joints, format});
  if (it != baked.end()) return it->second;
  si::Character c;
  c.name = "chain";
  si::Clip bend;
  bend.name = "bend";
  bend.duration_seconds = 1.0f;
  for (uint32_t i = 0; i < joints; ++i) {
    c.skeleton.joint_names.push_back("joint" + std::to_string(i));
    c.skeleton.parents.push_back(i == 0 ? si::Skeleton::kNoParent : int32_t(i - 1));
    si::Transform t;
    t.translation = i == 0 ? glm::vec3(0.0f) : glm::vec3(0, 0.05f, 0);
    c.skeleton.rest_pose.push_back(t);
    glm::mat4 ibm(1.0f);
    ibm[3] = glm::vec4(0, -0.05f * float(i), 0, 1);
    c.skeleton.inverse_bind_matrices.push_back(ibm);
    c.mesh.positions.push_back(glm::vec3(0.1f, 0.05f * float(i), 0.0f));
    c.mesh.normals.push_back(glm::vec3(1, 0, 0));
    c.mesh.joints.push_back(glm::u16vec4(uint16_t(i), 0, 0, 0));
    c.mesh.weights.push_back(glm::vec4(1, 0, 0, 0));
    si::JointTracks tracks;
    tracks.rotation.times_seconds = {0.0f, 1.0f};
    tracks.rotation.values = {glm::quat(1, 0, 0, 0), glm::angleAxis(0.05f, glm::vec3(1, 0, 0))};
    bend.joint_tracks.push_back(tracks);
  }
  for (uint32_t i = 0; i + 2 < joints; ++i)
    c.mesh.indices.insert(c.mesh.indices.end(), {i, i + 1, i + 2});
  c.mesh.sub_meshes.push_back(
      si::SubMesh{"body", {si::IndexRange{0, uint32_t(c.mesh.indices.size())}}, 0, {}});
  c.clips.push_back(bend);
  si::BakeDesc d;
  d.rate_mode = si::RateMode::kFixed;
  d.format = format;
  si::BakedPalette out;
  const si::Status s = si::bakePalette(c, d, &out, nullptr);
  if (!s.isOk()) {
    std::fprintf(stderr, "chainPalette: %s\n", s.toString().c_str());
    std::abort();
  }
  return baked.emplace(std::make_pair(joints, format), std::move(out)).first->second;
}

// setLivePose's cost against the joints a pose has: 1,000 instances of a chain of
// state.range(0) joints (chainPalette) posed each iteration with another baked frame, in a
// palette of float texels (state.range(1) 0, the default) or half floats (1); one call each
// (state.range(2) 0) or all in one setLivePoses on the crowd's workers (1: the default
// threads, the hardware's up to 16). ns_per_pose: one pose; ns_per_joint: that over the
// palette's joints.
void livePoseJoints(benchmark::State& state) {
  const si::BakedPalette& p =
      chainPalette(uint32_t(state.range(0)), state.range(1) != 0 ? si::PaletteFormat::kMatrix3x4F16
                                                                 : si::PaletteFormat::kDefault);
  constexpr uint32_t kLive = 1000;
  si::CrowdDesc cd;
  cd.palette = &p;
  cd.sub_mesh_count = 1;
  cd.live_pose_capacity = kLive;
  si::CrowdManager crowd;
  if (!crowd.init(cd).isOk()) std::abort();
  std::vector<si::InstanceHandle> handles(kLive);
  for (uint32_t k = 0; k < kLive; ++k) {
    si::InstanceDesc d;
    d.position = glm::dvec3(double(k % 40), 0.0, double(k / 40));
    if (!crowd.add(d, &handles[k]).isOk()) std::abort();
  }
  const std::vector<std::vector<glm::mat4>> poses = clipPoses(p);
  const bool batch = state.range(2) != 0;
  std::vector<glm::mat4> all;  // The batch's matrices, pose after pose.
  double set_ms = 0.0;
  uint32_t frame = 0;
  for (auto _ : state) {
    if (!crowd.advance(1.0 / 60.0).isOk()) std::abort();
    ++frame;
    if (batch) {  // Gathered untimed: an engine's poses lie in one array.
      all.clear();
      for (uint32_t k = 0; k < kLive; ++k) {
        const std::vector<glm::mat4>& pose = poses[(k + frame) % poses.size()];
        all.insert(all.end(), pose.begin(), pose.end());
      }
    }
    const auto t0 = std::chrono::steady_clock::now();
    if (batch) {
      if (!crowd.setLivePoses(handles, all).isOk()) std::abort();
    } else {
      for (uint32_t k = 0; k < kLive; ++k)
        if (!crowd.setLivePose(handles[k], poses[(k + frame) % poses.size()]).isOk()) std::abort();
    }
    set_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  const double n = double(state.iterations());
  state.counters["set_ms"] = set_ms / n;
  state.counters["ns_per_pose"] = set_ms * 1e6 / (n * kLive);
  state.counters["ns_per_joint"] = set_ms * 1e6 / (n * kLive * double(p.palette_joints.size()));
}
BENCHMARK(livePoseJoints)
    ->ArgNames({"joints", "half", "batch"})
    ->ArgsProduct({{20, 60}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

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
