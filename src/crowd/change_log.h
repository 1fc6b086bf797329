// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Which dense indices changed since a version (CrowdExport::changedSince, what the GPU-driven
// path uploads): the store stamps each index with the version its exported state last changed
// at (and the one its occupant did), and logs its recent changes, so that a consumer asking
// every frame reads the few that changed rather than every stamp (a churn of 1 % of a million:
// some 20,000 entries against two million stamps). No GL.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "si/crowd/gpu_crowd_state.h"

namespace si::detail {

/// The store's recent changes in version order (InstanceStore::changed logs each).
class ChangeLog {
 public:
  /// Starts over: changes up to `version` are found by their stamps only (the store's reset,
  /// and root motion, which stamps from parallel tasks without the log).
  void restart(uint64_t version);
  /// Index `i` changed at `version` (newer than every logged one); `placed`: another instance
  /// sits there now. Past `limit` entries the older half is dropped (found by the stamps).
  void add(uint64_t version, uint32_t i, bool placed, size_t limit);
  /// Whether every change after `since` is logged.
  bool holds(uint64_t since) const { return since >= floor_; }
  /// Whether since() is the faster way to find the changes after `since` among `n` indices:
  /// it holds them and they number under n / kEntriesPerIndex (each entry sets a bit, and the
  /// bits of n indices are cleared and read in order, where scanStamps reads two stamps an
  /// index in order; si_crowd_cpu_bench's churnExport measures both).
  bool answers(uint64_t since, uint32_t n) const;
  static constexpr uint64_t kEntriesPerIndex = 8;
  /// With holds(since): the indices below `n` stamped after `since` (the store's changed_at),
  /// as ascending runs of adjacent indices into `changed`, and those re-occupied after it (its
  /// placed_at) into `placed` (either may be null): what scanStamps finds, from the log alone.
  void since(uint64_t since, uint32_t n, std::vector<DenseRange>* changed,
             std::vector<DenseRange>* placed) const;
  size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    uint64_t version;
    uint32_t index;
    uint32_t placed;
  };
  // The first entry after version `since`.
  std::vector<Entry>::const_iterator firstAfter(uint64_t since) const;

  std::vector<Entry> entries_;
  uint64_t floor_ = 0;  // Every change after this version is logged.
};

/// The runs of adjacent indices below `n` stamped after `since` in `stamps`, skipping the
/// chunks of kStampChunk indices whose largest stamp (`chunk_stamps`) is not: every stamp read.
void scanStamps(const std::vector<uint64_t>& stamps, const std::vector<uint64_t>& chunk_stamps,
                uint64_t since, uint32_t n, std::vector<DenseRange>* out);

}  // namespace si::detail
