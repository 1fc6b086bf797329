// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Walking the dense indices of a list of runs (CrowdExport's ranged exports: what changed since
// an upload, scattered over the crowd by churn). Each index reads a dozen arrays at a random
// place, so the walk asks for the lines of the index kRunLookahead places ahead before it
// reads one (the misses overlap), and a long list is cut into tasks for the crowd's workers,
// each writing its own part of the output.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "si/core/span.h"
#include "si/crowd/gpu_crowd_state.h"
#include "si/crowd/parallel_for.h"

namespace si::detail {

/// Asks for the cache line holding `p` (a hint: nothing where the compiler has no builtin).
inline void prefetchLine(const void* p) {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

/// Indices between the one prefetched and the one read.
inline constexpr uint32_t kRunLookahead = 8;
/// Indices per task of a parallel walk; shorter lists run on the calling thread.
inline constexpr size_t kRunTaskIndices = 512;
/// The most tasks one walk is cut into.
inline constexpr size_t kRunTasks = 64;

/// A place in a list of runs: the run, and the index within it.
struct RunCursor {
  const DenseRange* run = nullptr;
  const DenseRange* end = nullptr;
  uint32_t at = 0;
  RunCursor() = default;
  RunCursor(const DenseRange* first, const DenseRange* last) : run(first), end(last) {
    skipEmpty();
  }
  bool done() const { return run == end; }
  uint32_t index() const { return run->first + at; }
  void next() {
    if (++at == run->count) ++run, at = 0, skipEmpty();
  }
  void skipEmpty() {
    while (run != end && run->count == 0) ++run;
  }
};

/// The indices of `runs` (`total` in all), in order: `ahead(index)` for the index
/// kRunLookahead places later, then `body(index, position)` (position: the index's place in
/// the walk, 0 to total - 1). Past kRunTaskIndices the walk is cut into tasks that
/// `parallel_for` runs (when it holds one); each task calls them for its own positions.
template <class Ahead, class Body>
void walkRuns(Span<const DenseRange> runs, size_t total, const ParallelFor& parallel_for,
              const Ahead& ahead, const Body& body) {
  const auto walk = [&](RunCursor at, size_t first, size_t count) {
    RunCursor lead = at;
    for (uint32_t k = 0; k < kRunLookahead && !lead.done(); ++k) lead.next();
    for (size_t p = first; p < first + count; ++p, at.next()) {
      if (!lead.done()) ahead(lead.index()), lead.next();
      body(at.index(), p);
    }
  };
  const RunCursor start(runs.begin(), runs.end());
  const size_t tasks = std::min(kRunTasks, (total + kRunTaskIndices - 1) / kRunTaskIndices);
  if (tasks <= 1 || !parallel_for) return walk(start, 0, total);
  // Each task's first place, found in one pass over the runs.
  const size_t per = (total + tasks - 1) / tasks;
  std::array<RunCursor, kRunTasks> starts;
  RunCursor c = start;
  size_t position = 0;
  for (size_t t = 0; t < tasks; ++t) {
    const size_t first = t * per;
    while (position < first && !c.done()) {  // Whole runs at a time where they fit.
      const size_t left = c.run->count - c.at;
      if (position + left <= first) {
        position += left, ++c.run, c.at = 0, c.skipEmpty();
      } else {
        c.at += uint32_t(first - position), position = first;
      }
    }
    starts[t] = c;
  }
  using Walk = decltype(walk);
  struct Task {
    const Walk* run;
    const std::array<RunCursor, kRunTasks>* starts;
    size_t per, total;
  } task{&walk, &starts, per, total};
  const Task* t = &task;  // One pointer: the std::function does not allocate.
  parallel_for(uint32_t(tasks), [t](uint32_t k) {
    const size_t first = k * t->per;
    if (first < t->total) (*t->run)((*t->starts)[k], first, std::min(t->per, t->total - first));
  });
}

}  // namespace si::detail
