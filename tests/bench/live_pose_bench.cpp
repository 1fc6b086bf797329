// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// What live poses cost the CPU (CrowdManager::setLivePose and setLivePoses; docs/crowd.md,
// "Live poses"): the calls in a field of 100,000 with the selection after them, the calls
// against the joints a pose has, and the GPU-driven path's upload of what they wrote. Part of
// si_crowd_cpu_bench (crowd_cpu_bench.cpp holds its main). Run:
// build/release/tests/bench/si_crowd_cpu_bench --benchmark_filter=livePose
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "crowd_bench_fixtures.h"
#include "si/bake/animation_baker.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"

namespace {

using si::bench::clipPoses;
using si::bench::field;
using si::bench::palette;

// A batch's matrices as an engine holds them, pose after pose in one array: `count` poses of
// `poses`, the k-th its (k + frame)-th.
void gatherPoses(const std::vector<std::vector<glm::mat4>>& poses, size_t count, uint32_t frame,
                 std::vector<glm::mat4>* all) {
  all->clear();
  for (size_t k = 0; k < count; ++k) {
    const std::vector<glm::mat4>& pose = poses[(k + frame) % poses.size()];
    all->insert(all->end(), pose.begin(), pose.end());
  }
}

// Live poses (CrowdManager::setLivePose; docs/crowd.md, "Live poses"): each iteration advances
// the clock, gives `live` instances of a field of 100,000 (every tenth) a new pose of the
// embedded character's 21 palette joints (a baked frame's matrices, another one each time:
// every live frame written), then selects at the new clock (update(0)), the frame order an
// engine follows; one setLivePose call each on one thread (batch 0), or one setLivePoses
// with the crowd on the default threads, the hardware's up to 16, the selection's too (batch
// 1). set_ms: the poses' share per iteration; select_ms: the selection's; ns_per_pose: one
// pose. Compare select_ms with live 0 for what posed instances add to the selection.
void livePoses(benchmark::State& state) {
  const int64_t count = 100000, live = state.range(0);
  const bool batch = state.range(1) != 0;
  auto crowd = field(count, -1.0f, batch ? 0 : 1, 0, false, uint32_t(std::max<int64_t>(live, 1)));
  std::vector<si::InstanceHandle> handles;
  std::vector<si::GpuInstanceState> states;
  si::CrowdExport(*crowd).state(&states, &handles);
  const si::BakedPalette& p = palette();
  const std::vector<std::vector<glm::mat4>> poses = clipPoses(p);
  const si::Camera camera =
      si::Camera::lookAt({237.0, 9.0, -7.0}, {237.0, 0.0, 45.0}, glm::vec3(0, 1, 0), 0.9f,
                         16.0f / 9.0f, 0.2f, 2000.0f);
  std::vector<si::InstanceHandle> posed;  // Every tenth.
  for (int64_t k = 0; k < live; ++k) posed.push_back(handles[size_t(k) * 10]);
  std::vector<glm::mat4> all;  // The batch's matrices, pose after pose.
  double set_ms = 0.0, select_ms = 0.0;
  uint32_t frame = 0;
  for (auto _ : state) {
    if (!crowd->advance(1.0 / 60.0).isOk()) std::abort();
    ++frame;
    if (batch) gatherPoses(poses, posed.size(), frame, &all);  // Untimed.
    const auto t0 = std::chrono::steady_clock::now();
    if (batch) {
      if (!crowd->setLivePoses(posed, all).isOk()) std::abort();
    } else {
      for (size_t k = 0; k < posed.size(); ++k)
        if (!crowd->setLivePose(posed[k], poses[(k + frame) % poses.size()]).isOk()) std::abort();
    }
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
    ->ArgsProduct({{0, 1000, 10000}, {0, 1}})
    ->ArgNames({"live", "batch"})
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
// threads, the hardware's up to 16). state.range(3), upload: 0 the calls alone; 1 and 2 then
// what the GPU-driven path's submit does for them on the CPU (src/gl/resources/
// palette_texture.cpp, src/gl/paths/gpu_culled_path.cpp and gpu_state_upload.cpp): the texels
// written since the last upload copied into a staging buffer (1: one memcpy on the calling
// thread; 2: CrowdExport::copyLivePoseTexels, on the crowd's workers past 256 KiB), the slots
// exported, and the changed instances' states. set_ms and upload_ms: each part's wall time per
// iteration; total_ms the two (the "calls and upload"); ns_per_pose and ns_per_joint:
// the calls per pose and per palette joint.
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
  const int64_t upload = state.range(3);
  const si::CrowdExport exported(crowd);
  std::vector<uint8_t> staging(exported.livePoseTexels().size());
  std::vector<si::GpuLivePose> slots;
  std::vector<si::DenseRange> changed;
  std::vector<si::GpuInstanceState> states(kLive);
  uint64_t live_version = 0, state_version = 0;
  double upload_ms = 0.0;
  std::vector<glm::mat4> all;  // The batch's matrices, pose after pose.
  double set_ms = 0.0;
  uint32_t frame = 0;
  for (auto _ : state) {
    if (!crowd.advance(1.0 / 60.0).isOk()) std::abort();
    ++frame;
    if (batch) gatherPoses(poses, kLive, frame, &all);  // Untimed.
    const auto t0 = std::chrono::steady_clock::now();
    if (batch) {
      if (!crowd.setLivePoses(handles, all).isOk()) std::abort();
    } else {
      for (uint32_t k = 0; k < kLive; ++k)
        if (!crowd.setLivePose(handles[k], poses[(k + frame) % poses.size()]).isOk()) std::abort();
    }
    const auto t1 = std::chrono::steady_clock::now();
    if (upload != 0) {
      uint32_t first = 0, count = 0;
      exported.livePoseTexelsChangedSince(live_version, &first, &count);
      const size_t bytes = si::bytesPerTexel(p.format);
      if (upload == 1)
        std::memcpy(staging.data(), exported.livePoseTexels().data() + size_t(first) * bytes,
                    size_t(count) * bytes);
      else
        exported.copyLivePoseTexels(first, count, staging.data());
      exported.livePoses(&slots);
      exported.changedSince(state_version, &changed, nullptr);
      exported.state(changed, states.data(), nullptr);
      live_version = exported.livePoseVersion();
      state_version = exported.stateVersion();
      benchmark::DoNotOptimize(staging.data());
      benchmark::DoNotOptimize(states.data());
    }
    const auto t2 = std::chrono::steady_clock::now();
    set_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
    upload_ms += std::chrono::duration<double, std::milli>(t2 - t1).count();
  }
  const double n = double(state.iterations());
  state.counters["set_ms"] = set_ms / n;
  state.counters["upload_ms"] = upload_ms / n;
  state.counters["total_ms"] = (set_ms + upload_ms) / n;
  state.counters["ns_per_pose"] = set_ms * 1e6 / (n * kLive);
  state.counters["ns_per_joint"] = set_ms * 1e6 / (n * kLive * double(p.palette_joints.size()));
}
BENCHMARK(livePoseJoints)
    ->ArgNames({"joints", "half", "batch", "upload"})
    ->ArgsProduct({{20, 60}, {0, 1}, {0, 1}, {0}})
    ->ArgsProduct({{60}, {0, 1}, {1}, {1, 2}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
