// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Live poses as GPU-driven culling reads them (CrowdExport): each posed instance's state names
// its slot, each slot its current frame (the one its record names) and its hand-over, and
// every change of either is a change the renderer uploads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <utility>
#include <vector>

#include "crowd/live_pose_helpers.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using test::defaultCharacter;
using test::defaultPalette;
using test::enginePose;
using test::liveDesc;
using test::recordOf;

// Instance `h`'s exported state.
GpuInstanceState stateOf(const CrowdManager& crowd, InstanceHandle h) {
  std::vector<GpuInstanceState> states;
  std::vector<InstanceHandle> handles;
  CrowdExport(crowd).state(&states, &handles);
  for (size_t i = 0; i < handles.size(); ++i)
    if (handles[i] == h) return states[i];
  ADD_FAILURE() << "no such instance";
  return GpuInstanceState();
}

// Whether `h`'s dense index is among the indices changed since `version`.
bool changedSince(const CrowdManager& crowd, InstanceHandle h, uint64_t version) {
  std::vector<InstanceHandle> handles;
  std::vector<GpuInstanceState> states;
  CrowdExport(crowd).state(&states, &handles);
  const uint32_t i = uint32_t(std::find(handles.begin(), handles.end(), h) - handles.begin());
  std::vector<DenseRange> changed;
  CrowdExport(crowd).changedSince(version, &changed, nullptr);
  for (const DenseRange& r : changed)
    if (i >= r.first && i - r.first < r.count) return true;
  return false;
}

TEST(LivePoseExport, StatesNameTheirSlotsAndSlotsTheirFramesAndHandOvers) {
  const BakedPalette& p = defaultPalette();
  const std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, p);
  const Camera camera = test::testCamera({0, 1.6, 6}, {0, 1, 0});
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(liveDesc(3)).isOk());
  InstanceDesc d;
  d.clip = uint32_t(p.findClip("walk"));
  InstanceHandle posed, playing;
  ASSERT_TRUE(crowd.add(d, &posed).isOk());
  ASSERT_TRUE(crowd.add(d, &playing).isOk());
  ASSERT_TRUE(crowd.update(0.25, camera).isOk());
  const CrowdExport e(crowd);
  std::vector<GpuLivePose> slots;
  e.livePoses(&slots);
  ASSERT_EQ(slots.size(), 3u);  // Every slot, held or not.
  EXPECT_EQ(stateOf(crowd, posed).live_pose, kGpuNoLivePose);

  // Fading in over 0.5 s from the crowd clock: slot, frame and fade exported, and a change.
  uint64_t version = e.stateVersion(), live_version = e.livePoseVersion();
  ASSERT_TRUE(crowd.setLivePose(posed, pose, 0.5).isOk());
  EXPECT_TRUE(changedSince(crowd, posed, version));
  EXPECT_FALSE(changedSince(crowd, playing, version));
  EXPECT_NE(e.livePoseVersion(), live_version);
  const uint32_t slot = stateOf(crowd, posed).live_pose;
  ASSERT_LT(slot, 3u);
  EXPECT_EQ(stateOf(crowd, playing).live_pose, kGpuNoLivePose);
  ASSERT_TRUE(crowd.update(0.1, camera).isOk());
  e.livePoses(&slots);
  EXPECT_EQ(slots[slot].first_texel, recordOf(crowd, posed)->frames[0]);
  EXPECT_GE(slots[slot].first_texel, e.livePoseFirstTexel());
  EXPECT_EQ(slots[slot].weight_from, 0.0f);
  EXPECT_EQ(slots[slot].weight_to, 1.0f);
  EXPECT_DOUBLE_EQ(slots[slot].fade_start, 0.25);
  EXPECT_DOUBLE_EQ(slots[slot].fade_duration, 0.5);

  // A pose set in a new step goes to the other frame: the slot names it. The instance's
  // state is as it was (it names the same slot): nothing for the GPU-driven path to upload
  // again but the slots and texels, which livePoseVersion() names.
  const uint32_t before = slots[slot].first_texel;
  version = e.stateVersion();
  live_version = e.livePoseVersion();
  const GpuInstanceState held = stateOf(crowd, posed);
  ASSERT_TRUE(crowd.setLivePose(posed, pose).isOk());
  e.livePoses(&slots);
  EXPECT_NE(slots[slot].first_texel, before);
  EXPECT_NE(e.livePoseVersion(), live_version);
  EXPECT_FALSE(changedSince(crowd, posed, version));
  const GpuInstanceState now = stateOf(crowd, posed);
  EXPECT_EQ(std::memcmp(&held, &now, sizeof(held)), 0);

  // Handing back over 0.2 s: from the weight it has (0.2 of the 0.5 s blend gone) to 0,
  // without a write (the fade alone changes the slot and the version).
  live_version = e.livePoseVersion();
  ASSERT_TRUE(crowd.clearLivePose(posed, 0.2).isOk());
  EXPECT_NE(e.livePoseVersion(), live_version);
  e.livePoses(&slots);
  EXPECT_NEAR(slots[slot].weight_from, 0.2f, 1e-6f);
  EXPECT_EQ(slots[slot].weight_to, 0.0f);
  EXPECT_DOUBLE_EQ(slots[slot].fade_start, 0.35);
  EXPECT_DOUBLE_EQ(slots[slot].fade_duration, 0.2);

  // Freed once the clip is back: the state names no slot again, a change to upload.
  version = e.stateVersion();
  ASSERT_TRUE(crowd.update(0.25, camera).isOk());
  EXPECT_EQ(stateOf(crowd, posed).live_pose, kGpuNoLivePose);
  EXPECT_TRUE(changedSince(crowd, posed, version));
}

// What a renderer uploads again: the frames written since the version it holds, the poses of
// one step together.
TEST(LivePoseExport, TheTexelsChangedSinceAVersionAreTheFramesWrittenSince) {
  const BakedPalette& p = defaultPalette();
  const uint32_t stride = p.layout.frame_stride_texels;
  const std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, p);
  const Camera camera = test::testCamera({0, 1.6, 6}, {0, 1, 0});
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(liveDesc(8)).isOk());
  std::vector<InstanceHandle> h(8);
  for (InstanceHandle& handle : h) ASSERT_TRUE(crowd.add(InstanceDesc(), &handle).isOk());
  const CrowdExport e(crowd);
  uint32_t first = 1, count = 1;
  e.livePoseTexelsChangedSince(0, &first, &count);  // Everything.
  EXPECT_EQ(first, 0u);
  EXPECT_EQ(size_t(count) * bytesPerTexel(p.format), e.livePoseTexels().size());
  e.livePoseTexelsChangedSince(e.livePoseVersion(), &first, &count);
  EXPECT_EQ(count, 0u);
  // Slots 0-3 taken in one step: frames 0-3 of side 0.
  uint64_t since = e.livePoseVersion();
  for (int k = 0; k < 4; ++k) ASSERT_TRUE(crowd.setLivePose(h[size_t(k)], pose).isOk());
  e.livePoseTexelsChangedSince(since, &first, &count);
  EXPECT_EQ(first, 0u);
  EXPECT_EQ(count, 4 * stride);
  // The next step writes slots 1 and 2 again: their side-1 frames (after the 8 of side 0),
  // and the slots' current frames are there.
  ASSERT_TRUE(crowd.update(0.1, camera).isOk());
  since = e.livePoseVersion();
  ASSERT_TRUE(crowd.setLivePose(h[1], pose).isOk());
  ASSERT_TRUE(crowd.setLivePose(h[2], pose).isOk());
  e.livePoseTexelsChangedSince(since, &first, &count);
  EXPECT_EQ(first, (8 + 1) * stride);
  EXPECT_EQ(count, 2 * stride);
  std::vector<GpuLivePose> slots;
  e.livePoses(&slots);
  EXPECT_EQ(slots[stateOf(crowd, h[1]).live_pose].first_texel, e.livePoseFirstTexel() + first);
  // A hand-back changes the version, not the texels.
  since = e.livePoseVersion();
  ASSERT_TRUE(crowd.clearLivePose(h[3], 0.5).isOk());
  EXPECT_NE(e.livePoseVersion(), since);
  e.livePoseTexelsChangedSince(since, &first, &count);
  EXPECT_EQ(count, 0u);
}

// What the renderer copies into its staging ring: the span's bytes exactly, on the crowd's
// workers past 256 KiB (as on the calling thread), nothing outside the span, and nothing at all
// for a span past the texels.
TEST(LivePoseExport, CopiedTexelsAreTheSpansBytes) {
  const BakedPalette& p = defaultPalette();
  const std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, p);
  constexpr uint32_t kPoses = 1500;  // 1.5 MB of float texels: 23 tasks.
  for (const uint32_t threads : {1u, 4u}) {
    SCOPED_TRACE(threads);
    CrowdDesc desc = liveDesc(kPoses);
    desc.worker_threads = threads;
    CrowdManager crowd;
    ASSERT_TRUE(crowd.init(desc).isOk());
    std::vector<InstanceHandle> h(kPoses);
    std::vector<glm::mat4> poses;  // Each pose moved by its own amount: no two alike.
    for (uint32_t k = 0; k < kPoses; ++k) {
      ASSERT_TRUE(crowd.add(InstanceDesc(), &h[k]).isOk());
      for (glm::mat4 m : pose) {
        m[3] += glm::vec4(0.001f * float(k), -0.002f * float(k % 97), 0.0f, 0.0f);
        poses.push_back(m);
      }
    }
    ASSERT_TRUE(crowd.setLivePoses(h, poses).isOk());
    const CrowdExport e(crowd);
    uint32_t first = 0, count = 0;
    e.livePoseTexelsChangedSince(0, &first, &count);
    const size_t texel = bytesPerTexel(p.format), guard = 64;
    const Span<const uint8_t> texels = e.livePoseTexels();
    // The whole, a span that starts and ends inside a frame, and one texel.
    const std::pair<uint32_t, uint32_t> spans[] = {
        {first, count}, {7, count / 2 - 11}, {count - 1, 1}};
    for (const auto& [at, n] : spans) {
      std::vector<uint8_t> out(size_t(n) * texel + 2 * guard, 0xCD);
      e.copyLivePoseTexels(at, n, out.data() + guard);
      EXPECT_TRUE(std::equal(texels.begin() + ptrdiff_t(size_t(at) * texel),
                             texels.begin() + ptrdiff_t(size_t(at + n) * texel),
                             out.begin() + ptrdiff_t(guard)))
          << at << " + " << n;
      EXPECT_TRUE(std::all_of(out.begin(), out.begin() + ptrdiff_t(guard),
                              [](uint8_t b) { return b == 0xCD; }));
      EXPECT_TRUE(std::all_of(out.end() - ptrdiff_t(guard), out.end(),
                              [](uint8_t b) { return b == 0xCD; }));
    }
    std::vector<uint8_t> out(texel * 2, 0xCD);
    e.copyLivePoseTexels(count - 1, 2, out.data());  // Past the texels: nothing.
    e.copyLivePoseTexels(0xFFFFFFFFu, 2, out.data());
    EXPECT_TRUE(std::all_of(out.begin(), out.end(), [](uint8_t b) { return b == 0xCD; }));
  }
}

TEST(LivePoseExport, ACrowdWithoutRoomExportsNoSlots) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(liveDesc(0)).isOk());
  std::vector<GpuLivePose> slots(2);
  CrowdExport(crowd).livePoses(&slots);
  EXPECT_TRUE(slots.empty());
  CrowdManager none;  // Not initialised.
  slots.resize(2);
  CrowdExport(none).livePoses(&slots);
  EXPECT_TRUE(slots.empty());
  uint32_t first = 1, count = 1;
  CrowdExport(none).livePoseTexelsChangedSince(0, &first, &count);
  EXPECT_EQ(first + count, 0u);
}

}  // namespace
}  // namespace si
