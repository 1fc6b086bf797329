// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The changes since a version, from the log or the stamps (change_log.h).
#include "crowd/change_log.h"

#include <algorithm>

#include "crowd/changed_bits.h"
#include "crowd/instance_store.h"

namespace si::detail {

namespace {

// Sorted distinct indices as runs of adjacent ones. Until 2026-11-28 runs closer than 64
// indices were merged (an upload call cost more then): a churn of 1 % of a million, 10,000
// scattered indices, uploaded 142,000 instances a frame.
void appendRun(uint32_t i, std::vector<DenseRange>* out) {
  if (!out->empty() && i == out->back().first + out->back().count)
    ++out->back().count;
  else
    out->push_back(DenseRange{i, 1});
}

}  // namespace

void ChangeLog::restart(uint64_t version) {
  entries_.clear();
  floor_ = version;
}

void ChangeLog::add(uint64_t version, uint32_t i, bool placed, size_t limit) {
  if (entries_.size() >= limit) {  // Keep the newer half: consumers ask every frame or so.
    const size_t drop = entries_.size() - limit / 2;
    floor_ = entries_[drop - 1].version;
    entries_.erase(entries_.begin(), entries_.begin() + std::ptrdiff_t(drop));
  }
  entries_.push_back(Entry{version, i, placed ? 1u : 0u});
}

std::vector<ChangeLog::Entry>::const_iterator ChangeLog::firstAfter(uint64_t since) const {
  return std::upper_bound(entries_.begin(), entries_.end(), since,
                          [](uint64_t v, const Entry& e) { return v < e.version; });
}

bool ChangeLog::answers(uint64_t since, uint32_t n) const {
  if (!holds(since)) return false;
  const auto first = firstAfter(since);
  return uint64_t(entries_.end() - first) * kEntriesPerIndex < n;
}

void ChangeLog::since(uint64_t since, uint32_t n, std::vector<DenseRange>* changed,
                      std::vector<DenseRange>* placed) const {
  // The log holds every change after `since`: an index below n was stamped after it exactly
  // when an entry after it names the index (an index past n was removed since). One bit an
  // index, set in any order: no stamp read at a random index, no sort. (Cutting this into
  // tasks over index ranges on the crowd's workers was tried, 2026-12-01: 0.39 against 0.42
  // ms on the H200's 16 cores, the tasks' start as dear as the work.)
  ChangedBits bits;
  bits.reserve(n);
  for (auto e = firstAfter(since); e != entries_.end(); ++e)
    if (e->index < n) bits.set(e->index, e->placed != 0);
  bits.take(n, changed, placed);
}

void scanStamps(const std::vector<uint64_t>& stamps, const std::vector<uint64_t>& chunk_stamps,
                uint64_t since, uint32_t n, std::vector<DenseRange>* out) {
  out->clear();
  for (uint32_t c = 0; c < chunk_stamps.size() && c * kStampChunk < n; ++c) {
    if (chunk_stamps[c] <= since) continue;
    const uint32_t end = std::min(n, (c + 1) * kStampChunk);
    for (uint32_t i = c * kStampChunk; i < end; ++i)
      if (stamps[i] > since) appendRun(i, out);
  }
}

}  // namespace si::detail
