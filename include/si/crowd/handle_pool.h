// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Typed handles with a generation counter: O(1) allocate and release, and a released (stale)
/// handle is reported as such, never taken for the instance that reuses its slot.

#include <cstdint>
#include <vector>

#include "si/core/status.h"

namespace si {

/// A handle: slot index in the low 20 bits, generation in the high 12. 0 is never valid.
struct InstanceHandle {
  uint32_t id = 0;
  bool operator==(const InstanceHandle& o) const { return id == o.id; }
  bool operator!=(const InstanceHandle& o) const { return id != o.id; }
};

/// State of a handle, as HandlePool::state() reports it.
enum class HandleState : uint8_t {
  kInvalid = 0,  ///< Never issued by this pool (or the null handle).
  kAlive,        ///< Issued and not released.
  kStale,        ///< Released; its slot may hold another instance now.
};

/// Allocates slots 0..capacity-1 and hands out generation-tagged handles to them. Not
/// thread-safe. Slot generations wrap after 4095 reuses, skipping 0, so a handle kept across
/// 4095 reuses of its slot would alias (documented limit of the 12-bit generation).
class HandlePool {
 public:
  static constexpr uint32_t kSlotBits = 20;
  static constexpr uint32_t kMaxSlots = 1u << kSlotBits;  ///< 1,048,576.

  /// Issues a handle for a free slot. Fails with kLimitExceeded when kMaxSlots are alive.
  Status allocate(InstanceHandle* out);
  /// Releases `h`. kNotFound for a stale or invalid handle (nothing changes).
  Status release(InstanceHandle h);
  /// Whether `h` is alive, stale or was never issued.
  HandleState state(InstanceHandle h) const;
  /// The slot of a live handle, or kNotFound (stale/invalid) with *slot untouched.
  Status slot(InstanceHandle h, uint32_t* slot) const;
  /// Live handles.
  uint32_t aliveCount() const { return alive_; }
  /// Slots ever used (the size slot-indexed arrays need).
  uint32_t slotCount() const { return static_cast<uint32_t>(generations_.size()); }
  /// The current handle of `slot` if alive, else the null handle.
  InstanceHandle handleAt(uint32_t slot) const;

 private:
  std::vector<uint16_t> generations_;  // Current generation per slot, 1..4095.
  std::vector<uint8_t> alive_flags_;
  std::vector<uint32_t> free_slots_;
  uint32_t alive_ = 0;
};

}  // namespace si
