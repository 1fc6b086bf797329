// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// drawCrowd's composed layers keyed per instance (crowd/composed_places.h): where the compose
// pass finds each record and which record each drawn slot reads.

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "crowd/composed_places.h"
#include "crowd/crowd_test_helpers.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

namespace si {
namespace {

// A crowd whose instances wear other sub-mesh sets, in batches of 5 records (each bucket cut
// into many), two buckets left undrawn (an LOD's sub-meshes without triangles): each record
// gets the first slot that draws it, its record where build() put it, and each drawn slot names its
// record; a record only the undrawn buckets hold gets no entry. The records composed are the
// instances drawn, fewer than the drawn slots (an instance wears several sub-meshes).
TEST(ComposedPlaces, EachDrawnInstanceIsComposedOnceAndEachSlotNamesIt) {
  CrowdDesc desc = test::defaultCrowdDesc();
  ASSERT_GE(desc.sub_mesh_count, 2u);
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(desc).isOk());
  std::vector<glm::dvec3> spots;
  for (int i = 0; i < 600; ++i) spots.push_back({(i % 30) * 1.5, 0.0, (i / 30) * 1.5});
  RandomCrowdDesc r;
  r.positions = spots;
  r.optional_mask = 0xE;
  ASSERT_TRUE(crowd.addRandom(r, nullptr).isOk());
  ASSERT_TRUE(crowd.update(0.1, test::testCamera({22, 10, -20}, {22, 0, 15})).isOk());
  const CrowdView& view = crowd.view();
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init({16384, 256, 5}).isOk());
  std::vector<uint8_t> buffer(batcher.recordBufferBound(view));
  std::vector<DrawBatch> draws;
  ASSERT_TRUE(batcher.build(view, buffer, &draws).isOk());
  const uint32_t subs = view.subMeshCount(), buckets = view.bucketCount();
  std::vector<uint8_t> drawn(buckets, 1);
  drawn[0] = drawn[1] = 0;  // LOD 0's sub-meshes 0 and 1 (the first buckets walked).
  const size_t records = view.records().size();
  std::vector<uint32_t> entries(records * 2, 7u);
  std::vector<uint32_t> slots(batcher.layerBufferBound(view) / kLayerRecordSize, 0xABCDu);
  const uint32_t composed = detail::writeComposedPlaces(batcher, view, drawn, entries, slots);

  // What the buckets say: the records the drawn ones hold, and the drawn slots.
  std::vector<bool> expected(records, false);
  size_t drawn_slots = 0;
  for (uint32_t b = 0; b < buckets; ++b)
    for (uint32_t e = view.bucketOffsets()[b]; e < view.bucketOffsets()[b + 1]; ++e)
      if (drawn[b] != 0) {
        expected[view.bucketEntries()[e]] = true;
        ++drawn_slots;
      }
  size_t expected_count = 0, only_undrawn = 0;
  for (uint32_t b = 0; b < buckets; ++b)
    for (uint32_t e = view.bucketOffsets()[b]; e < view.bucketOffsets()[b + 1]; ++e)
      only_undrawn += drawn[b] == 0 && !expected[view.bucketEntries()[e]];
  for (size_t i = 0; i < records; ++i) {
    expected_count += expected[i];
    if (!expected[i]) {
      EXPECT_EQ(entries[i * 2], detail::kNotComposed) << i;
      EXPECT_EQ(entries[i * 2 + 1], detail::kNotComposed) << i;
      continue;
    }
    InstanceRecord there;
    ASSERT_LE((size_t(entries[i * 2]) + 5) * 16, buffer.size()) << i;
    std::memcpy(&there, buffer.data() + size_t(entries[i * 2]) * 16, sizeof there);
    EXPECT_EQ(std::memcmp(&there, &view.records()[i], sizeof there), 0) << i;
    ASSERT_LT(entries[i * 2 + 1], slots.size());
    EXPECT_EQ(slots[entries[i * 2 + 1]], i);
  }
  EXPECT_EQ(composed, expected_count);
  EXPECT_LT(composed, drawn_slots);
  EXPECT_GT(only_undrawn, 0u);  // The undrawn buckets held someone drawn nowhere else.
  // Each drawn slot names the record build() put there.
  for (const DrawBatch& d : draws) {
    if (drawn[d.lod * subs + d.sub_mesh] == 0) continue;
    for (uint32_t k = 0; k < d.instance_count; ++k) {
      const uint32_t record = slots[d.layer_byte_offset / kLayerRecordSize + k];
      ASSERT_LT(record, records);
      EXPECT_EQ(std::memcmp(buffer.data() + d.byte_offset + k * kInstanceRecordSize,
                            &view.records()[record], kInstanceRecordSize),
                0);
    }
  }
}

}  // namespace
}  // namespace si
