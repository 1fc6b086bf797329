// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Which dense indices changed, as bits (CrowdExport::changedSince): one bit an index in each of
// two lists (changed, and re-occupied: another instance sits there now), and one bit a 64-index
// word saying it holds a change, read off as ascending runs visiting only those words.
// PendingChanges keeps them as the store changes, so that the consumer asking every frame (the
// GPU-driven path's upload) takes the frame's changes without a pass over the change log: a
// churn of 1 % of a million is some 20,000 bits set as the changes are made. No GL.

#include <atomic>
#include <cstdint>
#include <vector>

#include "si/crowd/gpu_crowd_state.h"

namespace si::detail {

/// Changed and re-occupied indices as bits.
class ChangedBits {
 public:
  /// Room for indices below `indices` (never shrinks).
  void reserve(uint32_t indices);
  /// Index `i` (below the reserved room) changed; `placed`: re-occupied too.
  void set(uint32_t i, bool placed) {
    const uint64_t bit = uint64_t(1) << (i % 64);
    changed_[i / 64] |= bit;
    if (placed) placed_[i / 64] |= bit;
    summary_[i / 4096] |= uint64_t(1) << ((i / 64) % 64);
  }
  /// Each list's indices below `n` as ascending runs of adjacent indices into its output
  /// (cleared first; either may be null), and every bit cleared.
  void take(uint32_t n, std::vector<DenseRange>* changed, std::vector<DenseRange>* placed);
  /// Every bit cleared.
  void clear();

 private:
  std::vector<uint64_t> changed_, placed_, summary_;
};

/// The changes made since the last take (InstanceStore::changed sets them): what the next
/// changedSince of that version reads. Copies hold the same bits.
class PendingChanges {
 public:
  PendingChanges() = default;
  PendingChanges(const PendingChanges& o) : bits_(o.bits_), since_(o.since_), valid_(o.valid_) {}
  PendingChanges& operator=(const PendingChanges& o) {
    bits_ = o.bits_;
    since_ = o.since_;
    valid_ = o.valid_;
    return *this;
  }
  /// Room for indices below `indices`.
  void reserve(uint32_t indices) { bits_.reserve(indices); }
  /// Index `i` changed (`placed`: re-occupied).
  void set(uint32_t i, bool placed) { bits_.set(i, placed); }
  /// Changes were made that the bits do not hold (stamps written from parallel tasks).
  void invalidate() { valid_ = false; }
  /// When the bits hold every change since `since` (the version of the last take), that is,
  /// the changes up to `now`: their runs below `n` into `changed` and `placed` (either may be
  /// null), and true. Otherwise false and nothing written. Either way the bits start over at
  /// `now`. A second thread calling while one takes gets false and leaves them alone.
  bool take(uint64_t since, uint64_t now, uint32_t n, std::vector<DenseRange>* changed,
            std::vector<DenseRange>* placed);

 private:
  ChangedBits bits_;
  uint64_t since_ = 0;
  bool valid_ = false;  // The bits hold every change after since_.
  std::atomic<bool> busy_{false};
};

}  // namespace si::detail
