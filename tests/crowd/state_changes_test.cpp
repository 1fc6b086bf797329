// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// What GPU-driven draws upload: CrowdManager::changedSince names exactly the dense indices whose
// exported state changed since a version (setters, play, root motion, add, remove), and those
// holding another instance; the range exports equal the whole exports there.
#include <gtest/gtest.h>

#include <cstring>

#include "crowd/crowd_test_helpers.h"

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
  crowd.exportGpuState(&state, &dense);
  for (uint32_t i = 0; i < dense.size(); ++i)
    if (dense[i] == h) return i;
  ADD_FAILURE() << "handle not found";
  return 0;
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
  crowd.changedSince(0, &changed, &placed);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].first, 0u);
  EXPECT_EQ(changed[0].count, 5000u);
  EXPECT_EQ(indices(placed), indices(changed));

  uint64_t since = crowd.stateVersion();
  crowd.changedSince(since, &changed, &placed);
  EXPECT_TRUE(changed.empty());
  EXPECT_TRUE(placed.empty());

  // Setters, far apart (their own runs), in several chunks; placed untouched.
  ASSERT_TRUE(crowd.setColor(h[10], glm::u8vec4(1, 2, 3, 255)).isOk());
  ASSERT_TRUE(crowd.setVariationMask(h[2100], 0x3).isOk());
  ASSERT_TRUE(crowd.play(h[4999], 1, 0.5, 1.0f).isOk());
  crowd.changedSince(since, &changed, &placed);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{10, 2100, 4999}));
  EXPECT_TRUE(placed.empty());
  // Only what changed after a later version.
  const uint64_t later = crowd.stateVersion();
  ASSERT_TRUE(crowd.setTransform(h[3000], glm::dvec3(1.0), glm::quat(1, 0, 0, 0), 2.0f).isOk());
  crowd.changedSince(later, &changed, nullptr);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{3000}));

  // Runs closer than 64 merge (the indices between are exported again).
  since = crowd.stateVersion();
  ASSERT_TRUE(crowd.crossfade(h[100], 2, 0.3).isOk());
  ASSERT_TRUE(crowd.setCustomLayer(h[150], 3).isOk());
  crowd.changedSince(since, &changed, nullptr);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].first, 100u);
  EXPECT_EQ(changed[0].count, 51u);

  // A removal moves the last instance into the hole: changed and placed there; the count falls.
  since = crowd.stateVersion();
  const uint32_t hole = denseOf(crowd, h[7]);
  ASSERT_TRUE(crowd.remove(h[7]).isOk());
  crowd.changedSince(since, &changed, &placed);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{hole}));
  EXPECT_EQ(indices(placed), (std::vector<uint32_t>{hole}));
  EXPECT_EQ(denseOf(crowd, h[4999]), hole);
  // An add is changed and placed at the end.
  since = crowd.stateVersion();
  InstanceHandle added;
  ASSERT_TRUE(crowd.add(InstanceDesc(), &added).isOk());
  crowd.changedSince(since, &changed, &placed);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{4999}));
  EXPECT_EQ(indices(placed), (std::vector<uint32_t>{4999}));
  // Removing the last instance changes nothing that remains.
  since = crowd.stateVersion();
  ASSERT_TRUE(crowd.remove(added).isOk());
  crowd.changedSince(since, &changed, &placed);
  EXPECT_TRUE(changed.empty());
  EXPECT_TRUE(placed.empty());
  // Neither an update (LODs, crossfade ends) nor the clock changes exported state.
  since = crowd.stateVersion();
  ASSERT_TRUE(crowd.update(0.5, test::testCamera({0, 2, -10}, {0, 0, 50})).isOk());
  ASSERT_TRUE(crowd.advanceClock(0.5).isOk());
  crowd.changedSince(since, &changed, &placed);
  EXPECT_TRUE(changed.empty());
}

// Root motion stamps the instances it moves, each frame; the range export equals the whole
// export on every index, and overlays likewise.
TEST(StateChanges, RootMotionStampsWhatMovedAndRangeExportsEqualTheWhole) {
  CrowdManager crowd;
  CrowdDesc cd = test::defaultCrowdDesc();
  cd.palette = &test::movingPalette();
  ASSERT_TRUE(crowd.init(cd).isOk());
  const uint32_t walk = uint32_t(test::movingPalette().findClip("walk_forward"));
  std::vector<InstanceHandle> h(3000);
  for (uint32_t i = 0; i < h.size(); ++i) {
    InstanceDesc d;
    d.position = glm::dvec3(double(i), 0.0, 0.0);
    d.clip = walk;
    d.root_motion = i % 1000 == 5;  // Three walkers, in three chunks.
    ASSERT_TRUE(crowd.add(d, &h[i]).isOk());
  }
  uint64_t since = crowd.stateVersion();
  for (int frame = 0; frame < 3; ++frame) {
    ASSERT_TRUE(crowd.advance(0.1).isOk());
    std::vector<DenseRange> changed, placed;
    crowd.changedSince(since, &changed, &placed);
    EXPECT_EQ(indices(changed), (std::vector<uint32_t>{5, 1005, 2005})) << frame;
    EXPECT_TRUE(placed.empty());
    since = crowd.stateVersion();
  }
  ASSERT_TRUE(crowd.advance(0.0).isOk());  // No time, no motion.
  std::vector<DenseRange> changed;
  crowd.changedSince(since, &changed, nullptr);
  EXPECT_TRUE(changed.empty());

  std::vector<GpuInstanceState> whole;
  std::vector<InstanceHandle> dense;
  crowd.exportGpuState(&whole, &dense);
  const DenseRange range{995, 20};
  std::vector<GpuInstanceState> part(range.count);
  std::vector<InstanceHandle> part_handles(range.count);
  crowd.exportGpuState(range, part.data(), part_handles.data());
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
  EXPECT_FALSE(crowd.playsOverlays());
  since = crowd.stateVersion();
  ASSERT_TRUE(crowd.playOverlay(h[1000], walk, mask, 0.7f, 0.2).isOk());
  EXPECT_TRUE(crowd.playsOverlays());
  crowd.changedSince(since, &changed, nullptr);
  EXPECT_EQ(indices(changed), (std::vector<uint32_t>{1000}));
  std::vector<GpuOverlayState> overlays, part_overlays(range.count);
  crowd.exportGpuOverlays(&overlays);
  crowd.exportGpuOverlays(range, part_overlays.data());
  for (uint32_t k = 0; k < range.count; ++k)
    EXPECT_EQ(std::memcmp(&part_overlays[k], &overlays[range.first + k], sizeof(GpuOverlayState)),
              0) << k;
  EXPECT_EQ(part_overlays[1000 - range.first].active, 1u);
  // A range past the end writes nothing.
  GpuInstanceState sentinel{};
  sentinel.scale = 7.0f;
  crowd.exportGpuState(DenseRange{2990, 11}, &sentinel, nullptr);
  EXPECT_EQ(sentinel.scale, 7.0f);
}

}  // namespace
}  // namespace si
