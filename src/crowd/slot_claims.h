// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// setLivePoses' claims on live slots, made from several threads at once: the batch's first
// claim on a slot wins it (its pose is stored and committed on the worker that claimed it), a
// second claim marks the slot as named twice (its poses are then set again in order, on the
// calling thread). Each batch gets a number of its own, so nothing is cleared between batches.
// No GL.

#include <atomic>
#include <cstdint>
#include <memory>

namespace si::detail {

class SlotClaims {
 public:
  /// A new batch over `slots` slots: no slot claimed.
  void start(uint32_t slots) {
    if (slots != size_ || batch_ == ~0u) {
      // Zeroed (value-initialised): batch numbers start at 1.
      claims_.reset(new std::atomic<uint32_t>[slots]());
      twice_.reset(new std::atomic<uint32_t>[slots]());
      size_ = slots;
      batch_ = 0;
    }
    ++batch_;
  }
  /// Claims `slot` for this batch: true for its first claim; a later one marks it named twice.
  /// Any thread.
  bool claim(uint32_t slot) {
    if (claims_[slot].exchange(batch_, std::memory_order_relaxed) != batch_) return true;
    twice_[slot].store(batch_, std::memory_order_relaxed);
    return false;
  }
  /// Whether this batch claimed `slot` more than once (after every claim is made).
  bool namedTwice(uint32_t slot) const {
    return twice_[slot].load(std::memory_order_relaxed) == batch_;
  }

 private:
  std::unique_ptr<std::atomic<uint32_t>[]> claims_, twice_;  // Per slot: a batch number.
  uint32_t size_ = 0, batch_ = 0;
};

}  // namespace si::detail
