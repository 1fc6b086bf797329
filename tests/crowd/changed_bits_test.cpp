// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The changes kept as bits (crowd/changed_bits.h): read off as the runs a sorted list of the
// indices makes, past a size dropped, cleared once taken; and taken only by the caller whose
// version they start at, through CrowdExport::changedSince as well.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "crowd/changed_bits.h"
#include "crowd/crowd_test_helpers.h"
#include "si/crowd/crowd_export.h"

namespace si {
namespace {

// The runs of adjacent indices of a sorted set, those below `n`.
std::vector<DenseRange> runsOf(const std::set<uint32_t>& indices, uint32_t n) {
  std::vector<DenseRange> out;
  for (uint32_t i : indices) {
    if (i >= n) break;
    if (!out.empty() && out.back().first + out.back().count == i)
      ++out.back().count;
    else
      out.push_back(DenseRange{i, 1});
  }
  return out;
}

bool sameRuns(const std::vector<DenseRange>& a, const std::vector<DenseRange>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](auto x, auto y) {
           return x.first == y.first && x.count == y.count;
         });
}

// Bits and, beside them, the sorted sets they should give.
struct Marked {
  detail::ChangedBits bits;
  std::set<uint32_t> changed, placed;
  void set(uint32_t i, bool p) {
    bits.set(i, p);
    changed.insert(i);
    if (p) placed.insert(i);
  }
};

// Random sets of scattered indices, whole 64-index words, runs across words and the last
// index, some re-occupied, read off below a random bound: the sorted sets' runs, exactly.
TEST(ChangedBits, TheRunsAreTheSortedIndicesRuns) {
  std::mt19937 rng(20261203);
  detail::ChangedBits bits;
  uint32_t room = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const uint32_t size = 1 + uint32_t(rng() % 20000);
    room = std::max(room, size);
    bits.reserve(size);
    Marked m{std::move(bits), {}, {}};
    const auto set = [&m](uint32_t i, bool p) { m.set(i, p); };
    const int shapes = 1 + int(rng() % 40);
    for (int k = 0; k < shapes; ++k) {
      const uint32_t at = uint32_t(rng() % size);
      const bool p = rng() % 3 == 0;
      switch (rng() % 4) {
        case 0:
          set(at, p);
          break;
        case 1:  // A whole word (or what of it fits).
          for (uint32_t i = at / 64 * 64; i < std::min(size, at / 64 * 64 + 64); ++i) set(i, p);
          break;
        case 2:  // A run across words.
          for (uint32_t i = at; i < std::min(size, at + 1 + uint32_t(rng() % 300)); ++i) set(i, p);
          break;
        default:
          set(size - 1, p);
          break;
      }
    }
    const uint32_t n = rng() % 4 == 0 ? uint32_t(rng() % (size + 1)) : size;
    std::vector<DenseRange> got_changed{{7, 7}}, got_placed;  // Cleared first.
    m.bits.take(n, &got_changed, &got_placed);
    ASSERT_TRUE(sameRuns(got_changed, runsOf(m.changed, n))) << "trial " << trial;
    ASSERT_TRUE(sameRuns(got_placed, runsOf(m.placed, n))) << "trial " << trial;
    m.bits.take(room, &got_changed, &got_placed);  // Taken: nothing left, past n neither.
    ASSERT_TRUE(got_changed.empty() && got_placed.empty()) << "trial " << trial;
    bits = std::move(m.bits);  // The same bits again: reused, cleared by the take.
  }
}

// The bits answer only the version they started at, then start over at the taker's.
TEST(ChangedBits, OnlyTheVersionTheyStartAtTakesThem) {
  detail::PendingChanges pending;
  pending.reserve(1000);
  std::vector<DenseRange> changed, placed;
  pending.set(5, false);
  EXPECT_FALSE(pending.take(0, 10, 1000, &changed, &placed));  // Never taken: from version 10.
  pending.set(6, true);
  pending.set(7, false);
  ASSERT_TRUE(pending.take(10, 12, 1000, &changed, &placed));
  EXPECT_TRUE(sameRuns(changed, {{6, 2}}));  // Not 5: it was before version 10.
  EXPECT_TRUE(sameRuns(placed, {{6, 1}}));
  pending.set(8, false);
  EXPECT_FALSE(pending.take(11, 14, 1000, &changed, &placed));  // Another caller's version.
  pending.set(9, false);
  ASSERT_TRUE(pending.take(14, 15, 1000, &changed, &placed));
  EXPECT_TRUE(sameRuns(changed, {{9, 1}}));
  EXPECT_TRUE(placed.empty());
  pending.set(10, false);
  pending.invalidate();  // Changes it does not hold.
  EXPECT_FALSE(pending.take(15, 16, 1000, &changed, &placed));
  EXPECT_TRUE(pending.take(16, 16, 1000, &changed, &placed));
  EXPECT_TRUE(changed.empty());
}

// Through the crowd: a caller that asks every frame and one that asks every other frame both
// get exactly the stamps' answer (the second from the log, the bits then starting over).
TEST(ChangedBits, TwoCallersAtTheirOwnVersionsGetTheirOwnChanges) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(test::defaultCrowdDesc()).isOk());
  std::vector<InstanceHandle> handles;
  for (int i = 0; i < 3000; ++i) {
    InstanceDesc d;
    d.position = glm::dvec3(i % 60, 0.0, i / 60);
    handles.emplace_back();
    ASSERT_TRUE(crowd.add(d, &handles.back()).isOk());
  }
  std::mt19937 rng(7);
  uint64_t every = CrowdExport(crowd).stateVersion(), other = every;
  std::set<uint32_t> since_every, since_other;
  for (int frame = 0; frame < 40; ++frame) {
    for (int k = 0; k < 30; ++k) {
      const uint32_t i = uint32_t(rng() % handles.size());
      ASSERT_TRUE(crowd.setColor(handles[i], glm::u8vec4(uint8_t(frame), 1, 2, 255)).isOk());
      // The handles' order is the dense order: no instance was added or removed.
      since_every.insert(i);
      since_other.insert(i);
    }
    std::vector<DenseRange> changed, placed;
    CrowdExport(crowd).changedSince(every, &changed, &placed);
    ASSERT_TRUE(sameRuns(changed, runsOf(since_every, 3000))) << "frame " << frame;
    every = CrowdExport(crowd).stateVersion();
    since_every.clear();
    if (frame % 2 == 1) {
      CrowdExport(crowd).changedSince(other, &changed, &placed);
      ASSERT_TRUE(sameRuns(changed, runsOf(since_other, 3000))) << "frame " << frame;
      other = CrowdExport(crowd).stateVersion();
      since_other.clear();
    }
  }
}

}  // namespace
}  // namespace si
