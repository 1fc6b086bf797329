// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>

#include "crowd/crowd_test_helpers.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

#include "crowd/allocation_counter.h"  // This binary counts its allocations.

namespace si {
namespace {
using test::defaultCrowdDesc;
using test::testCamera;

TEST(InstanceBatcher, CapacityFollowsTheUniformBlockLimit) {
  InstanceBatcher b;
  ASSERT_TRUE(b.init({65536, 256, 0}).isOk());
  EXPECT_EQ(b.capacityPerDraw(), 819u);
  ASSERT_TRUE(b.init({16384, 16, 0}).isOk());
  EXPECT_EQ(b.capacityPerDraw(), 204u);
  ASSERT_TRUE(b.init({65536, 0, 100}).isOk());
  EXPECT_EQ(b.capacityPerDraw(), 100u);
  EXPECT_EQ(b.alignment(), 256u);
  EXPECT_EQ(b.init({8192, 256, 0}).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(b.init({65536, 48, 0}).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(b.init({65536, 256, 900}).code(), StatusCode::kInvalidArgument);
}

class BatcherScene : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(crowd_.init(defaultCrowdDesc()).isOk());
    std::vector<glm::dvec3> positions;
    for (int i = 0; i < 3000; ++i) positions.push_back(glm::dvec3(i % 60, 0, i / 60) * 1.5);
    RandomCrowdDesc r;
    r.positions = positions;
    r.optional_mask = 0xE;
    ASSERT_TRUE(crowd_.addRandom(r, nullptr).isOk());
    camera_ = testCamera({45, 12, -20}, {45, 0, 40});
    ASSERT_TRUE(crowd_.update(1.0 / 60.0, camera_).isOk());
  }
  CrowdManager crowd_;
  Camera camera_;
};

// buildSpans: the same entries per bucket, in order, read in place from records(); every block
// binding aligned and within the block's capacity.
TEST_F(BatcherScene, SpansReadTheBucketsRecordsInPlaceWithAlignedBlocks) {
  for (BatchLimits limits : {BatchLimits{65536, 256, 0}, BatchLimits{16384, 16, 0},
                             BatchLimits{65536, 64, 37}, BatchLimits{16384, 256, 0}}) {
    InstanceBatcher b;
    ASSERT_TRUE(b.init(limits).isOk());
    std::vector<RecordSpanDraw> spans;
    const Status built = b.buildSpans(crowd_.view(), &spans);
    ASSERT_TRUE(built.isOk()) << built.message();
    const uint32_t sub_meshes = crowd_.desc().sub_mesh_count;
    std::map<uint32_t, std::vector<uint32_t>> per_bucket;
    for (const RecordSpanDraw& d : spans) {
      EXPECT_GT(d.instance_count, 0u);
      EXPECT_EQ(size_t(d.block_first_record) * kInstanceRecordSize % b.alignment(), 0u);
      EXPECT_LE(d.block_first_record, d.first_record);
      EXPECT_LE(d.first_record - d.block_first_record + d.instance_count, b.capacityPerDraw());
      EXPECT_LE(size_t(d.first_record) + d.instance_count, crowd_.view().records().size());
      std::vector<uint32_t>& got = per_bucket[d.lod * sub_meshes + d.sub_mesh];
      for (uint32_t k = 0; k < d.instance_count; ++k) got.push_back(d.first_record + k);
    }
    for (uint32_t bucket = 0; bucket < crowd_.view().bucketCount(); ++bucket) {
      const std::vector<uint32_t> expected(
          crowd_.view().bucketEntries().begin() + crowd_.view().bucketOffsets()[bucket],
          crowd_.view().bucketEntries().begin() + crowd_.view().bucketOffsets()[bucket + 1]);
      EXPECT_EQ(per_bucket[bucket], expected) << "bucket " << bucket;
    }
    // The random armour gives several masks, so a few more draws than buckets, not per instance.
    EXPECT_LE(spans.size(), crowd_.view().stats().visible / 10)
        << limits.uniform_buffer_offset_alignment;
  }
  // An alignment that puts a block start further before a draw than a block holds.
  InstanceBatcher coarse;
  ASSERT_TRUE(coarse.init({16384, 65536, 0}).isOk());
  std::vector<RecordSpanDraw> spans;
  EXPECT_EQ(coarse.buildSpans(crowd_.view(), &spans).code(), StatusCode::kUnsupported);
  EXPECT_EQ(coarse.buildSpans(crowd_.view(), nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(InstanceBatcher().buildSpans(crowd_.view(), &spans).code(),
            StatusCode::kInvalidArgument);
}

TEST_F(BatcherScene, BatchesRespectCapacityAlignmentAndCoverEveryEntryOnce) {
  for (BatchLimits limits : {BatchLimits{65536, 256, 0}, BatchLimits{16384, 16, 0},
                             BatchLimits{65536, 64, 37}}) {
    InstanceBatcher b;
    ASSERT_TRUE(b.init(limits).isOk());
    std::vector<uint8_t> buffer(b.recordBufferBound(crowd_.view()));
    std::vector<DrawBatch> draws;
    ASSERT_TRUE(b.build(crowd_.view(), buffer, &draws).isOk());
    const uint32_t sub_meshes = crowd_.desc().sub_mesh_count;
    std::map<uint32_t, uint32_t> per_bucket;
    uint64_t total = 0;
    for (const DrawBatch& d : draws) {
      EXPECT_GT(d.instance_count, 0u);
      EXPECT_LE(d.instance_count, b.capacityPerDraw());
      EXPECT_EQ(d.byte_offset % b.alignment(), 0u);
      EXPECT_LE(size_t(d.byte_offset) + d.instance_count * kInstanceRecordSize, buffer.size());
      per_bucket[d.lod * sub_meshes + d.sub_mesh] += d.instance_count;
      total += d.instance_count;
    }
    EXPECT_EQ(total, crowd_.view().stats().bucket_entries);
    // Draw calls: at most ceil(bucket size / capacity) per (LOD, sub-mesh).
    std::map<uint32_t, uint32_t> draws_per_bucket;
    for (const DrawBatch& d : draws) ++draws_per_bucket[d.lod * sub_meshes + d.sub_mesh];
    for (uint32_t bucket = 0; bucket < crowd_.view().bucketCount(); ++bucket) {
      const uint32_t n =
          crowd_.view().bucketOffsets()[bucket + 1] - crowd_.view().bucketOffsets()[bucket];
      EXPECT_EQ(per_bucket[bucket], n);
      EXPECT_EQ(draws_per_bucket[bucket], (n + b.capacityPerDraw() - 1) / b.capacityPerDraw());
    }
    // Each bucket's records are exactly its visible instances, each once, in order.
    size_t d_index = 0;
    for (uint32_t bucket = 0; bucket < crowd_.view().bucketCount(); ++bucket) {
      uint32_t entry = crowd_.view().bucketOffsets()[bucket];
      while (entry < crowd_.view().bucketOffsets()[bucket + 1]) {
        const DrawBatch& d = draws[d_index++];
        for (uint32_t k = 0; k < d.instance_count; ++k, ++entry) {
          const InstanceRecord& expected =
              crowd_.view().records()[crowd_.view().bucketEntries()[entry]];
          ASSERT_EQ(0, std::memcmp(buffer.data() + d.byte_offset + k * kInstanceRecordSize,
                                   &expected, kInstanceRecordSize));
        }
      }
    }
    EXPECT_EQ(d_index, draws.size());
  }
}

// buildHandles (host materials that read the instance handle): in buildLayers' slot numbering,
// each slot holds the handle of the instance whose record build() put in that slot.
TEST_F(BatcherScene, HandlesSitInTheSlotsOfTheirRecords) {
  const CrowdView& view = crowd_.view();
  for (BatchLimits limits : {BatchLimits{65536, 256, 0}, BatchLimits{16384, 16, 0}}) {
    InstanceBatcher b;
    ASSERT_TRUE(b.init(limits).isOk());
    std::vector<uint8_t> records(b.recordBufferBound(view)), handles(b.handleBufferBound(view));
    EXPECT_EQ(handles.size(), b.layerBufferBound(view) / 4);
    std::vector<DrawBatch> draws;
    ASSERT_TRUE(b.build(view, records, &draws).isOk());
    ASSERT_TRUE(b.buildHandles(view, handles).isOk());
    size_t d_index = 0, checked = 0;
    for (uint32_t bucket = 0; bucket < crowd_.view().bucketCount(); ++bucket) {
      uint32_t entry = crowd_.view().bucketOffsets()[bucket];
      while (entry < crowd_.view().bucketOffsets()[bucket + 1]) {
        const DrawBatch& d = draws[d_index++];
        for (uint32_t k = 0; k < d.instance_count; ++k, ++entry, ++checked) {
          uint32_t id = 0;
          std::memcpy(&id, handles.data() + (d.layer_byte_offset / kLayerRecordSize + k) * 4, 4);
          ASSERT_EQ(id, view.visibleHandles()[crowd_.view().bucketEntries()[entry]].id);
        }
      }
    }
    EXPECT_EQ(checked, crowd_.view().stats().bucket_entries);
    std::vector<uint8_t> small(handles.size() - 1, 0xAB);
    EXPECT_EQ(b.buildHandles(view, small).code(), StatusCode::kCountMismatch);
    EXPECT_EQ(small, std::vector<uint8_t>(handles.size() - 1, 0xAB));  // Nothing written.
  }
  std::vector<uint8_t> any(64);
  EXPECT_EQ(InstanceBatcher().buildHandles(view, any).code(), StatusCode::kInvalidArgument);
}

TEST_F(BatcherScene, WornSubMeshesOnlyAndEveryVisibleInstanceInItsLodBuckets) {
  const uint32_t sub_meshes = crowd_.desc().sub_mesh_count;
  std::vector<uint32_t> seen(crowd_.view().records().size(), 0);
  for (uint32_t bucket = 0; bucket < crowd_.view().bucketCount(); ++bucket) {
    const uint32_t lod = bucket / sub_meshes, sm = bucket % sub_meshes;
    for (uint32_t e = crowd_.view().bucketOffsets()[bucket];
         e < crowd_.view().bucketOffsets()[bucket + 1]; ++e) {
      const uint32_t v = crowd_.view().bucketEntries()[e];
      InstanceDesc d;
      ASSERT_TRUE(crowd_.get(crowd_.view().visibleHandles()[v], &d).isOk());
      EXPECT_TRUE((d.variation_mask >> sm) & 1u);
      uint32_t l = 99;
      ASSERT_TRUE(crowd_.view().lodOf(crowd_.view().visibleHandles()[v], &l).isOk());
      EXPECT_EQ(l, lod);
      if (sm == 0) ++seen[v];
    }
  }
  for (uint32_t count : seen) EXPECT_EQ(count, 1u);  // The body: once per visible instance.
  EXPECT_GT(crowd_.view().stats().visible, 100u);
  EXPECT_GT(crowd_.view().stats().culled_frustum, 100u);
}

TEST_F(BatcherScene, DeterministicAndErrorsLeaveOutputAlone) {
  InstanceBatcher b;
  ASSERT_TRUE(b.init({65536, 256, 0}).isOk());
  std::vector<uint8_t> one(b.recordBufferBound(crowd_.view())), two(one.size());
  std::vector<DrawBatch> d1, d2;
  ASSERT_TRUE(b.build(crowd_.view(), one, &d1).isOk());
  ASSERT_TRUE(b.build(crowd_.view(), two, &d2).isOk());
  EXPECT_EQ(one, two);
  ASSERT_EQ(d1.size(), d2.size());
  std::vector<uint8_t> small(one.size() - 1, 0xAB);
  EXPECT_EQ(b.build(crowd_.view(), small, &d2).code(), StatusCode::kCountMismatch);
  EXPECT_EQ(small[0], 0xAB);
  EXPECT_EQ(b.build(crowd_.view(), one, nullptr).code(), StatusCode::kInvalidArgument);
  InstanceBatcher uninitialized;
  EXPECT_EQ(uninitialized.build(crowd_.view(), one, &d2).code(), StatusCode::kInvalidArgument);
}

TEST_F(BatcherScene, NoAllocationPerFrameOnceWarmedUp) {
  InstanceBatcher b;
  ASSERT_TRUE(b.init({65536, 256, 0}).isOk());
  std::vector<uint8_t> buffer(1 << 22);
  std::vector<DrawBatch> draws;
  draws.reserve(4096);
  ASSERT_TRUE(b.build(crowd_.view(), buffer, &draws).isOk());
  ASSERT_TRUE(crowd_.update(1.0 / 60.0, camera_).isOk());  // Warm-up at this crowd size.
  g_allocations = 0;
  g_counting = true;
  // Codes only while counting (a failure's message would allocate, and so would gtest); every
  // frame must have updated and built, or the count says nothing.
  StatusCode codes[2 * 10];
  int frames = 0;
  for (; frames < 10; ++frames) {
    codes[2 * frames] = crowd_.update(1.0 / 60.0, camera_).code();
    codes[2 * frames + 1] = b.build(crowd_.view(), buffer, &draws).code();
    if (codes[2 * frames] != StatusCode::kOk || codes[2 * frames + 1] != StatusCode::kOk) break;
  }
  g_counting = false;
  ASSERT_EQ(frames, 10) << "frame " << frames << " failed: update "
                        << statusCodeName(codes[2 * frames]) << ", build "
                        << statusCodeName(codes[2 * frames + 1]);
  EXPECT_FALSE(draws.empty());
  EXPECT_EQ(g_allocations.load(), 0u);
}

}  // namespace
}  // namespace si
