// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager::setLivePoses: a batch of poses, stored on several threads, leaves the crowd as
// the same calls one by one do (hand-overs from the clip, poses set again in a step, a handle
// named twice, fades back in), whoever runs its tasks; a refused pose is named and the others
// are set.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "crowd/live_pose_helpers.h"
#include "si/crowd/crowd_export.h"

namespace si {
namespace {

using test::defaultCharacter;
using test::defaultPalette;
using test::liveDesc;

constexpr uint32_t kInstances = 150;

// Pose `k` of a batch: the engine's pose moved along x by a step of its own.
std::vector<glm::mat4> poseOf(uint32_t k) {
  std::vector<glm::mat4> pose = test::enginePose(defaultCharacter().skeleton, defaultPalette());
  for (glm::mat4& m : pose) m[3].x += 0.01f * float(k % 97);
  return pose;
}

struct Crowd {
  CrowdManager crowd;
  std::vector<InstanceHandle> handles;
  explicit Crowd(uint32_t threads) {
    CrowdDesc d = liveDesc(kInstances);
    d.worker_threads = threads;
    EXPECT_TRUE(crowd.init(d).isOk());
    for (uint32_t k = 0; k < kInstances; ++k) {
      InstanceDesc i;
      i.position = glm::dvec3(double(k % 15), 0.0, -double(k / 15));
      i.clip = k % uint32_t(defaultPalette().clips.size());
      handles.push_back(InstanceHandle());
      EXPECT_TRUE(crowd.add(i, &handles.back()).isOk());
    }
  }
};

// A batch: which instances (by index, repeats allowed) and which pose each gets.
struct Batch {
  std::vector<uint32_t> instances, poses;
  double blend = 0.0;
};

std::vector<glm::mat4> matricesOf(const Batch& b) {
  std::vector<glm::mat4> out;
  for (uint32_t pose : b.poses) {
    const std::vector<glm::mat4> m = poseOf(pose);
    out.insert(out.end(), m.begin(), m.end());
  }
  return out;
}

// The live version each crowd's consumer last uploaded at.
struct Seen {
  uint64_t a = 0, b = 0;
};

// What every consumer of the live poses reads: the texels, the slots' export (frames, hand-overs
// and bounds), the count, the span of texels written since `seen` (the version moves on alike,
// though a batch's poses share one), and the records the next selection writes.
void expectSame(CrowdManager& a, CrowdManager& b, const char* when, Seen* seen) {
  const CrowdExport ea(a), eb(b);
  EXPECT_EQ(ea.livePoseCount(), eb.livePoseCount()) << when;
  EXPECT_EQ(ea.livePoseVersion() > seen->a, eb.livePoseVersion() > seen->b) << when;
  uint32_t first_a = 0, count_a = 0, first_b = 0, count_b = 0;
  ea.livePoseTexelsChangedSince(seen->a, &first_a, &count_a);
  eb.livePoseTexelsChangedSince(seen->b, &first_b, &count_b);
  EXPECT_EQ(first_a, first_b) << when;
  EXPECT_EQ(count_a, count_b) << when;
  *seen = {ea.livePoseVersion(), eb.livePoseVersion()};
  EXPECT_TRUE(std::equal(ea.livePoseTexels().begin(), ea.livePoseTexels().end(),
                         eb.livePoseTexels().begin(), eb.livePoseTexels().end()))
      << when;
  std::vector<GpuLivePose> sa, sb;
  ea.livePoses(&sa);
  eb.livePoses(&sb);
  ASSERT_EQ(sa.size(), sb.size());
  EXPECT_EQ(std::memcmp(sa.data(), sb.data(), sa.size() * sizeof(GpuLivePose)), 0) << when;
  const Camera camera = test::testCamera({7.0, 3.0, 8.0}, {7.0, 1.0, -4.0});
  ASSERT_TRUE(a.update(0.0, camera).isOk());
  ASSERT_TRUE(b.update(0.0, camera).isOk());
  ASSERT_EQ(a.view().records().size(), b.view().records().size()) << when;
  EXPECT_EQ(std::memcmp(a.view().records().data(), b.view().records().data(),
                        a.view().records().size() * sizeof(InstanceRecord)),
            0)
      << when;
}

TEST(LivePoseBatch, EqualsTheCallsOneByOne) {
  // Step 1: from their clips (one at a time inside the batch). Step 2: held since step 1
  // (stored on the workers), a handle named twice, one from its clip named twice, a blend.
  // Then some handed back over a blend and posed again in the same step (fading in again),
  // and a second batch in that step (over the current frames).
  std::vector<std::vector<Batch>> steps(3);
  for (uint32_t k = 0; k < 120; ++k) steps[0].push_back({{k}, {k}});
  Batch all;
  for (uint32_t k = 0; k < kInstances; ++k) all.instances.push_back(k), all.poses.push_back(k + 3);
  all.instances.insert(all.instances.begin() + 40, 5), all.poses.insert(all.poses.begin() + 40, 77);
  all.instances.push_back(130), all.poses.push_back(11);  // From its clip, named twice.
  all.blend = 0.2;
  steps[1] = {all};
  Batch again = all, once_more;
  for (uint32_t& p : again.poses) p += 5;
  for (uint32_t k = 0; k < 60; k += 3)
    once_more.instances.push_back(k), once_more.poses.push_back(k);
  steps[2] = {again, once_more};

  // Tasks run by the crowd's workers, by one thread, and by a host's loop that runs them last
  // first.
  const ParallelFor backwards = [](uint32_t count, const ParallelTask& task) {
    for (uint32_t t = count; t > 0; --t) task(t - 1);
  };
  for (int runner = 0; runner < 3; ++runner) {
    Crowd batched(runner == 1 ? 1u : 0u), single(1);
    Seen seen;
    for (size_t s = 0; s < steps.size(); ++s) {
      ASSERT_TRUE(batched.crowd.advance(1.0 / 30.0).isOk());
      ASSERT_TRUE(single.crowd.advance(1.0 / 30.0).isOk());
      // What changed in the step (the instances the GPU-driven path uploads again).
      const uint64_t since_batched = CrowdExport(batched.crowd).stateVersion();
      const uint64_t since_single = CrowdExport(single.crowd).stateVersion();
      if (s == 2)  // Handed back over a blend before the batch poses them again.
        for (uint32_t k = 100; k < 110; ++k) {
          ASSERT_TRUE(batched.crowd.clearLivePose(batched.handles[k], 0.5).isOk());
          ASSERT_TRUE(single.crowd.clearLivePose(single.handles[k], 0.5).isOk());
        }
      for (const Batch& b : steps[s]) {
        std::vector<InstanceHandle> handles;
        for (uint32_t i : b.instances) handles.push_back(batched.handles[i]);
        const std::vector<glm::mat4> m = matricesOf(b);
        const Status st = batched.crowd.setLivePoses(handles, m, b.blend,
                                                     runner == 2 ? backwards : ParallelFor());
        ASSERT_TRUE(st.isOk()) << st.toString();
        for (size_t k = 0; k < b.instances.size(); ++k) {
          const std::vector<glm::mat4> pose = poseOf(b.poses[k]);
          ASSERT_TRUE(
              single.crowd.setLivePose(single.handles[b.instances[k]], pose, b.blend).isOk());
        }
      }
      std::vector<DenseRange> changed_batched, changed_single;
      CrowdExport(batched.crowd).changedSince(since_batched, &changed_batched, nullptr);
      CrowdExport(single.crowd).changedSince(since_single, &changed_single, nullptr);
      ASSERT_EQ(changed_batched.size(), changed_single.size());
      EXPECT_EQ(std::memcmp(changed_batched.data(), changed_single.data(),
                            changed_single.size() * sizeof(DenseRange)),
                0);
      EXPECT_FALSE(changed_single.empty());
      expectSame(batched.crowd, single.crowd,
                 runner == 0   ? "workers"
                 : runner == 1 ? "one thread"
                               : "host's loop",
                 &seen);
    }
  }
}

TEST(LivePoseBatch, ARefusalNamesItsPoseAndTheOthersAreSet) {
  Crowd batched(0), single(1);
  Seen seen;
  const uint32_t joints = uint32_t(defaultPalette().palette_joints.size());
  // Held since an earlier step: pose 2's NaN is found on the workers.
  for (Crowd* c : {&batched, &single}) {
    for (uint32_t k = 0; k < 4; ++k)
      ASSERT_TRUE(c->crowd.setLivePose(c->handles[k], poseOf(k)).isOk());
    ASSERT_TRUE(c->crowd.advance(1.0 / 30.0).isOk());
  }
  ASSERT_TRUE(batched.crowd.remove(batched.handles[9]).isOk());
  ASSERT_TRUE(single.crowd.remove(single.handles[9]).isOk());
  const std::vector<uint32_t> instances = {0, 1, 2, 3, 9, 20};  // 9 removed, 20 from its clip.
  std::vector<InstanceHandle> handles;
  std::vector<glm::mat4> m;
  for (size_t k = 0; k < instances.size(); ++k) {
    handles.push_back(batched.handles[instances[k]]);
    std::vector<glm::mat4> pose = poseOf(uint32_t(k) + 40);
    if (k == 2) pose[joints / 2][1][0] = std::nanf("");
    if (k == 5) pose[1][2][3] = 0.25f;  // A last row the palette cannot hold.
    m.insert(m.end(), pose.begin(), pose.end());
  }
  const Status s = batched.crowd.setLivePoses(handles, m);
  EXPECT_EQ(s.code(), StatusCode::kNotFinite);
  EXPECT_NE(s.message().find("setLivePoses: pose 2: "), std::string::npos) << s.message();
  // The same calls one by one: the others are set; 2 keeps its pose, 20 its clip.
  for (size_t k = 0; k < instances.size(); ++k) {
    const Status one = single.crowd.setLivePose(
        single.handles[instances[k]], Span<const glm::mat4>(m.data() + k * joints, joints));
    EXPECT_EQ(one.isOk(), k != 2 && k != 4 && k != 5) << k;
  }
  expectSame(batched.crowd, single.crowd, "after the refusals", &seen);

  // Every pose refused alike whoever finds it: the stale handle first when it comes first.
  const std::vector<InstanceHandle> stale_first = {batched.handles[9], batched.handles[0]};
  std::vector<glm::mat4> two(m.begin(), m.begin() + 2 * joints);
  const Status stale = batched.crowd.setLivePoses(stale_first, two);
  EXPECT_EQ(stale.code(), StatusCode::kNotFound);
  EXPECT_NE(stale.message().find("setLivePoses: pose 0: "), std::string::npos) << stale.message();
  const uint64_t version = CrowdExport(batched.crowd).livePoseVersion();
  two.pop_back();  // A pose short: nothing set.
  EXPECT_EQ(batched.crowd.setLivePoses(stale_first, two).code(), StatusCode::kCountMismatch);
  EXPECT_EQ(CrowdExport(batched.crowd).livePoseVersion(), version);
  CrowdManager none;
  ASSERT_TRUE(none.init(test::defaultCrowdDesc()).isOk());
  EXPECT_EQ(none.setLivePoses({}, {}).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(batched.crowd.setLivePoses({}, {}, -1.0).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(batched.crowd.setLivePoses({}, {}).isOk());  // An empty batch.
}

TEST(LivePoseBatch, AHostsParallelForRunsTheStores) {
  Crowd c(1);  // The crowd's own tasks on one thread: what runs them here is the host's.
  std::vector<InstanceHandle> handles(c.handles.begin(), c.handles.begin() + 100);
  Batch b;
  for (uint32_t k = 0; k < 100; ++k) b.instances.push_back(k), b.poses.push_back(k);
  const std::vector<glm::mat4> m = matricesOf(b);
  uint32_t sections = 0, tasks = 0;
  const ParallelFor host = [&](uint32_t count, const ParallelTask& task) {
    ++sections;
    for (uint32_t t = 0; t < count; ++t) task(t), ++tasks;
  };
  ASSERT_TRUE(c.crowd.setLivePoses(handles, m, 0.0, host).isOk());
  EXPECT_EQ(sections, 0u);  // From their clips: each stored one at a time.
  ASSERT_TRUE(c.crowd.advance(1.0 / 30.0).isOk());
  const uint64_t before = CrowdExport(c.crowd).livePoseVersion();
  ASSERT_TRUE(c.crowd.setLivePoses(handles, m, 0.0, host).isOk());
  EXPECT_EQ(sections, 1u);  // Held: stored straight into their other frames by the tasks.
  EXPECT_EQ(tasks, 4u);     // 32 poses a task.
  // Every pose committed by the tasks, none on this thread: the version still moves on, and
  // what was written since is their 100 frames (slots 0 to 99 of one side).
  const CrowdExport e(c.crowd);
  EXPECT_GT(e.livePoseVersion(), before);
  uint32_t first = 0, count = 0;
  e.livePoseTexelsChangedSince(before, &first, &count);
  EXPECT_EQ(count, 100u * defaultPalette().layout.frame_stride_texels);
}

}  // namespace
}  // namespace si
