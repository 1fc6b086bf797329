// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Changed indices as bits, read off as runs (changed_bits.h).
#include "crowd/changed_bits.h"

#include <algorithm>

namespace si::detail {

namespace {

int lowestBit(uint64_t word) {
#if defined(__GNUC__) || defined(__clang__)
  return __builtin_ctzll(word);
#else
  int bit = 0;
  for (; (word & 1u) == 0; word >>= 1) ++bit;
  return bit;
#endif
}

// The runs of set bits of `word` (indices from `base`) appended to `out`, the first joined to
// the last run there when adjacent. One step a run, not a bit: a word whose 64 indices all
// changed is one step.
void appendWordRuns(uint64_t word, uint32_t base, std::vector<DenseRange>* out) {
  while (word != 0) {
    const int start = lowestBit(word);
    const uint64_t from = word >> start;  // Ones from bit 0; zeros shifted in at the top.
    const int length = ~from == 0 ? 64 : lowestBit(~from);
    const uint32_t first = base + uint32_t(start);
    if (!out->empty() && out->back().first + out->back().count == first)
      out->back().count += uint32_t(length);
    else
      out->push_back(DenseRange{first, uint32_t(length)});
    word = start + length >= 64 ? 0 : word & (~uint64_t(0) << (start + length));
  }
}

}  // namespace

void ChangedBits::reserve(uint32_t indices) {
  const size_t words = (size_t(indices) + 63) / 64;
  if (words <= changed_.size()) return;
  // Half as much again, so that adds one at a time grow it a few times.
  const size_t grown = std::max(words, changed_.size() + changed_.size() / 2);
  changed_.resize(grown, 0);
  placed_.resize(grown, 0);
  summary_.resize((grown + 63) / 64, 0);
}

void ChangedBits::take(uint32_t n, std::vector<DenseRange>* changed,
                       std::vector<DenseRange>* placed) {
  if (changed != nullptr) changed->clear();
  if (placed != nullptr) placed->clear();
  for (size_t s = 0; s < summary_.size(); ++s) {
    for (uint64_t held = summary_[s]; held != 0; held &= held - 1) {
      const size_t w = s * 64 + size_t(lowestBit(held));
      const uint32_t base = uint32_t(w * 64);
      // Bits at or past n: indices removed since (dropped).
      const uint64_t below = base >= n        ? 0
                             : n - base >= 64 ? ~uint64_t(0)
                                              : (uint64_t(1) << (n - base)) - 1;
      if (changed != nullptr) appendWordRuns(changed_[w] & below, base, changed);
      if (placed != nullptr) appendWordRuns(placed_[w] & below, base, placed);
      changed_[w] = placed_[w] = 0;
    }
    summary_[s] = 0;
  }
}

void ChangedBits::clear() {
  std::fill(changed_.begin(), changed_.end(), 0);
  std::fill(placed_.begin(), placed_.end(), 0);
  std::fill(summary_.begin(), summary_.end(), 0);
}

bool PendingChanges::take(uint64_t since, uint64_t now, uint32_t n,
                          std::vector<DenseRange>* changed, std::vector<DenseRange>* placed) {
  if (busy_.exchange(true, std::memory_order_acquire)) return false;
  const bool held = valid_ && since == since_;
  if (held)
    bits_.take(n, changed, placed);
  else
    bits_.clear();
  since_ = now;
  valid_ = true;
  busy_.store(false, std::memory_order_release);
  return held;
}

}  // namespace si::detail
