// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Motion vectors, the crowd's half (CrowdDesc::previous_records): the previous update's records
// kept exactly, and per record the index of the same instance's record in them, or none for an
// instance not drawn then, added since or placed by setTransform() since; across crossfades,
// LOD changes, removals and any thread count.
#include <gtest/gtest.h>

#include <cstring>
#include <map>

#include "crowd/crowd_test_helpers.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

namespace si {
namespace {

bool sameRecord(const InstanceRecord& a, const InstanceRecord& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

struct Frame {
  std::vector<InstanceRecord> records;
  std::map<uint32_t, size_t> index_of;  // Handle id -> record index.
};

Frame capture(const CrowdManager& crowd) {
  Frame f;
  f.records.assign(crowd.view().records().begin(), crowd.view().records().end());
  for (size_t r = 0; r < crowd.view().visibleHandles().size(); ++r)
    f.index_of[crowd.view().visibleHandles()[r].id] = r;
  return f;
}

// Each record's previous index names the same instance's record of the frame before, which
// previousRecords() holds exactly; instances in `no_motion` (teleported) and those not drawn
// then have none.
void expectPrevious(const CrowdManager& crowd, const Frame& before,
                    const std::vector<uint32_t>& no_motion = {}) {
  ASSERT_EQ(crowd.view().previousRecords().size(), before.records.size());
  for (size_t r = 0; r < before.records.size(); ++r)
    ASSERT_TRUE(sameRecord(crowd.view().previousRecords()[r], before.records[r])) << r;
  ASSERT_EQ(crowd.view().previousRecordIndices().size(), crowd.view().records().size());
  for (size_t r = 0; r < crowd.view().records().size(); ++r) {
    const uint32_t id = crowd.view().visibleHandles()[r].id;
    const auto it = before.index_of.find(id);
    const bool teleported = std::find(no_motion.begin(), no_motion.end(), id) != no_motion.end();
    const uint32_t expected =
        it == before.index_of.end() || teleported ? kNoPreviousRecord : uint32_t(it->second);
    ASSERT_EQ(crowd.view().previousRecordIndices()[r], expected) << "record " << r << " id " << id;
  }
}

CrowdManager makeCrowd(uint32_t threads, bool previous = true) {
  CrowdDesc d = test::defaultCrowdDesc();
  d.previous_records = previous;
  d.worker_threads = threads;
  CrowdManager crowd;
  EXPECT_TRUE(crowd.init(d).isOk());
  return crowd;
}

TEST(PreviousRecords, EachRecordNamesWhatItsInstanceDrewLastUpdate) {
  for (uint32_t threads : {1u, 7u}) {
    SCOPED_TRACE(threads);
    CrowdManager crowd = makeCrowd(threads);
    // A field larger than one task (4096), partly out of view, so instances enter and leave.
    std::vector<glm::dvec3> spots;
    for (int i = 0; i < 9000; ++i) spots.push_back({(i % 95) * 1.5, 0.0, (i / 95) * 1.5});
    RandomCrowdDesc r;
    r.positions = spots;
    r.optional_mask = 0xE;
    std::vector<InstanceHandle> handles;
    ASSERT_TRUE(crowd.addRandom(r, &handles).isOk());
    Camera camera = test::testCamera({70, 10, -20}, {70, 0, 60});
    ASSERT_TRUE(crowd.update(1.0 / 60.0, camera).isOk());
    EXPECT_TRUE(crowd.view().previousRecords().empty());  // Nothing was drawn before.
    for (uint32_t k = 0; k < crowd.view().records().size(); ++k)
      ASSERT_EQ(crowd.view().previousRecordIndices()[k], kNoPreviousRecord);
    size_t with = 0, without = 0;  // Over the frames: something of each kind happened.
    for (int frame = 0; frame < 6; ++frame) {
      const Frame before = capture(crowd);
      std::vector<uint32_t> teleported;
      if (frame == 1) {  // Crossfades, a removal (the last instance moves into its hole), adds.
        for (size_t i = 0; i < handles.size(); i += 97)
          ASSERT_TRUE(crowd.crossfade(handles[i], 2, 0.5).isOk());
        ASSERT_TRUE(crowd.remove(handles[5]).isOk());
        InstanceDesc d;
        d.position = {70, 0, 5};
        InstanceHandle added;
        ASSERT_TRUE(crowd.add(d, &added).isOk());
      }
      if (frame == 2) {  // Teleports: a visible instance placed elsewhere has no motion vector.
        for (const auto& [id, index] : before.index_of) {
          InstanceHandle h;
          h.id = id;
          InstanceDesc d;
          ASSERT_TRUE(crowd.get(h, &d).isOk());
          // Near the middle of the view, so they are drawn again.
          if (teleported.size() < 5 && glm::length(d.position - glm::dvec3(70, 0, 25)) < 10.0) {
            ASSERT_TRUE(crowd.setTransform(h, d.position + glm::dvec3(0.5, 0, 0), d.rotation, d.scale).isOk());
            teleported.push_back(id);
          }
        }
      }
      // The camera moves: instances enter and leave the view and change LOD.
      camera = test::testCamera({70, 10, -20.0 + 6.0 * frame}, {70, 0, 60});
      ASSERT_TRUE(crowd.update(frame == 3 ? 0.0 : 0.1, camera).isOk());
      expectPrevious(crowd, before, teleported);
      size_t teleported_drawn = 0;
      for (InstanceHandle h : crowd.view().visibleHandles())
        teleported_drawn += std::count(teleported.begin(), teleported.end(), h.id);
      EXPECT_EQ(teleported_drawn, teleported.size());  // Checked where they are drawn.
      for (uint32_t p : crowd.view().previousRecordIndices())
        (p == kNoPreviousRecord ? without : with) += 1;
    }
    EXPECT_GT(with, 100u);
    EXPECT_GT(without, 0u);
  }
}

// The same indices whatever the thread count.
TEST(PreviousRecords, TheSameForAnyThreadCount) {
  std::vector<std::vector<uint32_t>> runs;
  for (uint32_t threads : {1u, 3u, 8u}) {
    CrowdManager crowd = makeCrowd(threads);
    std::vector<glm::dvec3> spots;
    for (int i = 0; i < 10000; ++i) spots.push_back({(i % 100) * 1.5, 0.0, (i / 100) * 1.5});
    RandomCrowdDesc r;
    r.positions = spots;
    ASSERT_TRUE(crowd.addRandom(r, nullptr).isOk());
    std::vector<uint32_t> all;
    for (int frame = 0; frame < 3; ++frame) {
      ASSERT_TRUE(crowd.update(0.1, test::testCamera({75, 12, -10.0 + 8 * frame}, {75, 0, 80})).isOk());
      all.insert(all.end(), crowd.view().previousRecordIndices().begin(),
                 crowd.view().previousRecordIndices().end());
    }
    runs.push_back(all);
  }
  EXPECT_EQ(runs[1], runs[0]);
  EXPECT_EQ(runs[2], runs[0]);
}

TEST(PreviousRecords, OffByDefault) {
  CrowdManager crowd = makeCrowd(1, false);
  InstanceDesc d;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  for (int i = 0; i < 2; ++i) ASSERT_TRUE(crowd.update(0.1, test::testCamera({0, 2, -6}, {0, 1, 0})).isOk());
  EXPECT_EQ(crowd.view().records().size(), 1u);
  EXPECT_TRUE(crowd.view().previousRecords().empty());
  EXPECT_TRUE(crowd.view().previousRecordIndices().empty());
}

TEST(PreviousRecords, TheCamerasOfTheLastTwoUpdates) {
  CrowdManager crowd = makeCrowd(1);
  const Camera a = test::testCamera({0, 2, -6}, {0, 1, 0}), b = test::testCamera({1, 2, -6}, {0, 1, 0});
  ASSERT_TRUE(crowd.update(0.1, a).isOk());
  EXPECT_EQ(crowd.view().camera().position, a.position);
  EXPECT_EQ(crowd.view().previousCamera().position, a.position);  // No update before: the same.
  ASSERT_TRUE(crowd.update(0.1, b).isOk());
  EXPECT_EQ(crowd.view().camera().position, b.position);
  EXPECT_EQ(crowd.view().previousCamera().position, a.position);
  EXPECT_EQ(crowd.view().previousCamera().viewProjection(), a.viewProjection());
}

// A frame is a step of the crowd: every update() and advance() counts one, dt 0
// included, a refused one none; init() starts over. Each setTransform() of an instance counts a
// placement in its exported state (the GPU-driven path's teleport mark), which moves with the
// instance when a removal moves it.
TEST(PreviousRecords, StepsAndPlacementsAreCounted) {
  CrowdManager crowd = makeCrowd(1);
  const Camera c = test::testCamera({0, 2, -6}, {0, 1, 0});
  EXPECT_EQ(crowd.stepCount(), 0u);
  ASSERT_TRUE(crowd.update(0.1, c).isOk());
  ASSERT_TRUE(crowd.update(0.0, c).isOk());
  ASSERT_TRUE(crowd.advance(0.0).isOk());
  ASSERT_TRUE(crowd.advance(0.0).isOk());
  EXPECT_EQ(crowd.advance(-1.0).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(crowd.stepCount(), 4u);
  EXPECT_EQ(crowd.clockSeconds(), 0.1);

  InstanceHandle a, b;
  InstanceDesc d;
  ASSERT_TRUE(crowd.add(d, &a).isOk());
  ASSERT_TRUE(crowd.add(d, &b).isOk());
  ASSERT_TRUE(crowd.setTransform(b, {1, 0, 0}, glm::quat(1, 0, 0, 0), 1.0f).isOk());
  ASSERT_TRUE(crowd.setTransform(b, {2, 0, 0}, glm::quat(1, 0, 0, 0), 1.0f).isOk());
  EXPECT_EQ(crowd.setTransform(b, {2, 0, 0}, glm::quat(0, 0, 0, 0), 1.0f).code(),
            StatusCode::kInvalidArgument);  // Refused: no placement.
  std::vector<GpuInstanceState> state;
  CrowdExport(crowd).state(&state, nullptr);
  ASSERT_EQ(state.size(), 2u);
  EXPECT_EQ(state[0].placement, 0u);
  EXPECT_EQ(state[1].placement, 2u);
  ASSERT_TRUE(crowd.remove(a).isOk());  // b moves to dense index 0 with its count.
  CrowdExport(crowd).state(&state, nullptr);
  ASSERT_EQ(state.size(), 1u);
  EXPECT_EQ(state[0].placement, 2u);

  ASSERT_TRUE(crowd.init(crowd.desc()).isOk());
  EXPECT_EQ(crowd.stepCount(), 0u);
}

// The batcher tests' scene: 3000 instances on a 60 x 50 grid with random clips and worn
// sub-meshes, and a batcher of 16 KiB blocks (many batches).
void makeBatcherScene(CrowdManager* crowd, std::vector<InstanceHandle>* handles,
                      InstanceBatcher* batcher) {
  std::vector<glm::dvec3> spots;
  for (int i = 0; i < 3000; ++i) spots.push_back({(i % 60) * 1.5, 0.0, (i / 60) * 1.5});
  RandomCrowdDesc r;
  r.positions = spots;
  r.optional_mask = 0xE;
  ASSERT_TRUE(crowd->addRandom(r, handles).isOk());
  ASSERT_TRUE(batcher->init({16384, 256, 0}).isOk());
}

// Its frame `frame`: the camera moves along the grid; before frame 2 every 50th instance is
// placed anew (a teleport: no previous record).
void batcherSceneFrame(int frame, const std::vector<InstanceHandle>& handles, CrowdManager* crowd) {
  if (frame == 2)
    for (size_t i = 0; i < handles.size(); i += 50) {
      InstanceDesc d;
      ASSERT_TRUE(crowd->get(handles[i], &d).isOk());
      ASSERT_TRUE(crowd->setTransform(handles[i], d.position, d.rotation, d.scale).isOk());
    }
  const Camera camera = test::testCamera({45, 10, -20.0 + 5.0 * frame}, {45, 0, 50});
  ASSERT_TRUE(crowd->update(0.1, camera).isOk());
}

// buildPrevious: build()'s slots, each holding its instance's previous record, or where it has
// none its current record moved from the last camera's origin to the previous one's. And
// buildPreviousIndices (what drawCrowd reads): in buildLayers' slot numbering, each slot's index
// into previousRecords(), kNoPreviousRecord exactly where buildPrevious took the fallback.
TEST(PreviousRecords, TheBatcherWritesThemInBuildsSlots) {
  CrowdManager crowd = makeCrowd(3);
  std::vector<InstanceHandle> handles;
  InstanceBatcher batcher;
  ASSERT_NO_FATAL_FAILURE(makeBatcherScene(&crowd, &handles, &batcher));
  size_t with = 0, without = 0;
  for (int frame = 0; frame < 4; ++frame) {
    ASSERT_NO_FATAL_FAILURE(batcherSceneFrame(frame, handles, &crowd));
    std::vector<uint8_t> current(batcher.recordBufferBound(crowd.view())), previous(current.size());
    std::vector<uint8_t> indices(batcher.previousIndexBufferBound(crowd.view()));
    EXPECT_EQ(indices.size(), batcher.layerBufferBound(crowd.view()) / 4);
    std::vector<DrawBatch> draws;
    ASSERT_TRUE(batcher.build(crowd.view(), current, &draws).isOk());
    ASSERT_TRUE(batcher.buildPrevious(crowd.view(), previous).isOk());
    ASSERT_TRUE(batcher.buildPreviousIndices(crowd.view(), indices).isOk());
    const glm::vec3 shift(crowd.view().camera().position - crowd.view().previousCamera().position);
    const std::vector<uint32_t>& entries = crowd.view().bucketEntries();
    size_t e = 0;
    for (const DrawBatch& d : draws)
      for (uint32_t k = 0; k < d.instance_count; ++k, ++e) {
        const uint32_t rec = entries[e], p = crowd.view().previousRecordIndices()[rec];
        InstanceRecord now, then;
        std::memcpy(&now, current.data() + d.byte_offset + k * kInstanceRecordSize, sizeof now);
        std::memcpy(&then, previous.data() + d.byte_offset + k * kInstanceRecordSize, sizeof then);
        ASSERT_TRUE(sameRecord(now, crowd.view().records()[rec]));
        InstanceRecord expected = crowd.view().records()[rec];
        if (p != kNoPreviousRecord) {
          expected = crowd.view().previousRecords()[p];
          ++with;
        } else {
          for (int row = 0; row < 3; ++row) expected.world_rows[row][3] += shift[row];
          ++without;
        }
        ASSERT_TRUE(sameRecord(then, expected)) << "frame " << frame << " record " << rec;
        uint32_t index;
        std::memcpy(&index, indices.data() + (d.layer_byte_offset / kLayerRecordSize + k) * 4, 4);
        ASSERT_EQ(index, p) << "frame " << frame << " record " << rec;
      }
    EXPECT_EQ(e, entries.size());
  }
  EXPECT_GT(with, 1000u);
  EXPECT_GT(without, 1000u);  // The first frame, instances entering the view, the teleported.
  std::vector<uint8_t> small(batcher.recordBufferBound(crowd.view()) - 1);
  EXPECT_EQ(batcher.buildPrevious(crowd.view(), small).code(), StatusCode::kCountMismatch);
  CrowdManager plain = makeCrowd(1, false);
  EXPECT_EQ(batcher.buildPrevious(plain.view(), small).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(InstanceBatcher().buildPrevious(crowd.view(), small).code(),
            StatusCode::kInvalidArgument);
  std::vector<uint8_t> few(batcher.previousIndexBufferBound(crowd.view()) - 1);
  EXPECT_EQ(batcher.buildPreviousIndices(crowd.view(), few).code(), StatusCode::kCountMismatch);
  EXPECT_EQ(batcher.buildPreviousIndices(plain.view(), few).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(InstanceBatcher().buildPreviousIndices(crowd.view(), few).code(),
            StatusCode::kInvalidArgument);
}

// drawCrowd's motion vectors without a copy: buildRecordPlaces says where build() put each record,
// and the next selection's buildPreviousIndices through that table points each slot at its
// previous record in the buffer the last frame's build() wrote, which holds buildPrevious's
// record there (the selection's records are the next one's previous records, byte for byte).
TEST(PreviousRecords, TheLastFramesBufferHoldsThePreviousRecords) {
  CrowdManager crowd = makeCrowd(3);
  std::vector<InstanceHandle> handles;
  InstanceBatcher batcher;
  ASSERT_NO_FATAL_FAILURE(makeBatcherScene(&crowd, &handles, &batcher));
  std::vector<uint8_t> last_buffer;
  std::vector<uint32_t> last_places;
  size_t through = 0, without = 0;
  const uint64_t selections = crowd.view().selectionCount();
  for (int frame = 0; frame < 4; ++frame) {
    ASSERT_NO_FATAL_FAILURE(batcherSceneFrame(frame, handles, &crowd));
    EXPECT_EQ(crowd.view().selectionCount(), selections + uint64_t(frame) + 1);
    std::vector<uint8_t> current(batcher.recordBufferBound(crowd.view())), previous(current.size());
    std::vector<uint8_t> indices(batcher.previousIndexBufferBound(crowd.view()));
    std::vector<DrawBatch> draws;
    ASSERT_TRUE(batcher.build(crowd.view(), current, &draws).isOk());
    ASSERT_TRUE(batcher.buildPrevious(crowd.view(), previous).isOk());
    if (frame > 0) {
      ASSERT_TRUE(batcher.buildPreviousIndices(crowd.view(), indices, last_places).isOk());
      for (const DrawBatch& d : draws)
        for (uint32_t k = 0; k < d.instance_count; ++k) {
          uint32_t word;
          std::memcpy(&word, indices.data() + (d.layer_byte_offset / kLayerRecordSize + k) * 4, 4);
          InstanceRecord then;
          std::memcpy(&then, previous.data() + d.byte_offset + k * kInstanceRecordSize,
                      sizeof then);
          if (word == kNoPreviousRecord) {
            ++without;  // buildPrevious' fallback: the current record moved.
            continue;
          }
          ASSERT_LE(size_t(word) * 16 + kInstanceRecordSize, last_buffer.size());
          InstanceRecord there;
          std::memcpy(&there, last_buffer.data() + size_t(word) * 16, sizeof there);
          ASSERT_TRUE(sameRecord(there, then)) << "frame " << frame << " slot " << k;
          ++through;
        }
    }
    std::vector<uint32_t> places(crowd.view().records().size() + 1, 7u);
    ASSERT_TRUE(batcher.buildRecordPlaces(crowd.view(), places).isOk());
    EXPECT_EQ(places.back(), 7u);  // Past records(): untouched.
    for (size_t i = 0; i < crowd.view().records().size(); ++i) {
      ASSERT_NE(places[i], InstanceBatcher::kNoRecordPlace);
      InstanceRecord there;
      std::memcpy(&there, current.data() + size_t(places[i]) * 16, sizeof there);
      ASSERT_TRUE(sameRecord(there, crowd.view().records()[i]))
          << "frame " << frame << " record " << i;
    }
    last_buffer = current;
    last_places.assign(places.begin(), places.end() - 1);
  }
  EXPECT_GT(through, 1000u);
  EXPECT_GT(without, 100u);  // Instances entering the view, the teleported.
  std::vector<uint8_t> indices(batcher.previousIndexBufferBound(crowd.view()));
  const Span<const uint32_t> short_table(last_places.data(),
                                         crowd.view().previousRecords().size() - 1);
  EXPECT_EQ(batcher.buildPreviousIndices(crowd.view(), indices, short_table).code(),
            StatusCode::kCountMismatch);
  std::vector<uint32_t> few(crowd.view().records().size() - 1);
  EXPECT_EQ(batcher.buildRecordPlaces(crowd.view(), few).code(), StatusCode::kCountMismatch);
  EXPECT_EQ(InstanceBatcher().buildRecordPlaces(crowd.view(), few).code(),
            StatusCode::kInvalidArgument);
}

// A camera cut past a float's range: the fallback keeps the current translation rather than
// writing an infinite one.
TEST(PreviousRecords, ACameraCutPastAFloatKeepsFiniteRecords) {
  CrowdManager crowd = makeCrowd(1);
  InstanceDesc d;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.update(0.1, test::testCamera({1e39, 2, -6}, {1e39, 1, 0})).isOk());
  ASSERT_TRUE(crowd.update(0.1, test::testCamera({0, 2, -6}, {0, 1, 0})).isOk());
  ASSERT_EQ(crowd.view().records().size(), 1u);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init({16384, 256, 0}).isOk());
  std::vector<uint8_t> previous(batcher.recordBufferBound(crowd.view()));
  ASSERT_TRUE(batcher.buildPrevious(crowd.view(), previous).isOk());
  InstanceRecord r;
  std::memcpy(&r, previous.data(), sizeof r);
  EXPECT_TRUE(sameRecord(r, crowd.view().records()[0]));
}

}  // namespace
}  // namespace si
