// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/crowd/handle_pool.h"

namespace si {
namespace {
constexpr uint32_t kSlotMask = HandlePool::kMaxSlots - 1;
constexpr uint16_t kMaxGeneration = 4095;
uint32_t makeId(uint32_t slot, uint16_t generation) {
  return (uint32_t(generation) << HandlePool::kSlotBits) | slot;
}
}  // namespace

Status HandlePool::allocate(InstanceHandle* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "HandlePool::allocate: out is null"};
  uint32_t s;
  if (!free_slots_.empty()) {
    s = free_slots_.back();
    free_slots_.pop_back();
  } else {
    if (generations_.size() >= kMaxSlots)
      return {StatusCode::kLimitExceeded, "HandlePool: all 1048576 slots are in use"};
    s = static_cast<uint32_t>(generations_.size());
    generations_.push_back(1);
    alive_flags_.push_back(0);
  }
  alive_flags_[s] = 1;
  ++alive_;
  out->id = makeId(s, generations_[s]);
  return Status::ok();
}

HandleState HandlePool::state(InstanceHandle h) const {
  const uint32_t s = h.id & kSlotMask;
  const uint32_t g = h.id >> kSlotBits;
  if (g == 0 || s >= generations_.size()) return HandleState::kInvalid;
  if (alive_flags_[s] && generations_[s] == g) return HandleState::kAlive;
  return HandleState::kStale;
}

Status HandlePool::release(InstanceHandle h) {
  if (state(h) != HandleState::kAlive)
    return {StatusCode::kNotFound, "HandlePool::release: handle is stale or invalid"};
  const uint32_t s = h.id & kSlotMask;
  alive_flags_[s] = 0;
  generations_[s] = generations_[s] == kMaxGeneration ? 1 : uint16_t(generations_[s] + 1);
  free_slots_.push_back(s);
  --alive_;
  return Status::ok();
}

Status HandlePool::slot(InstanceHandle h, uint32_t* out_slot) const {
  if (state(h) != HandleState::kAlive)
    return {StatusCode::kNotFound, "instance handle is stale or invalid"};
  if (out_slot != nullptr) *out_slot = h.id & kSlotMask;
  return Status::ok();
}

InstanceHandle HandlePool::handleAt(uint32_t s) const {
  if (s >= generations_.size() || !alive_flags_[s]) return InstanceHandle{};
  return InstanceHandle{makeId(s, generations_[s])};
}

}  // namespace si
