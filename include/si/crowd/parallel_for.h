// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// How CrowdManager::update() spreads its per-frame work over threads. The work is cut into
/// independent tasks over instance ranges; a ParallelFor runs them. An engine hands in one that
/// maps the tasks onto its own job system; without one, the crowd runs them on its own
/// std::thread workers (a WorkerPool, CrowdDesc::worker_threads). Whatever runs the tasks, and
/// in whatever order, the frame's records, buckets and statistics are the same: each task
/// writes only its own slots.
///
/// Usage with an engine's job system:
/// \code
///   si::ParallelFor pf = [&jobs](uint32_t count, const si::ParallelTask& task) {
///     jobs.parallelFor(0, count, [&](uint32_t i) { task(i); });  // returns when all ran
///   };
///   crowd.update(dt, camera, pf);
/// \endcode

#include <cstdint>
#include <functional>
#include <memory>

namespace si {

/// One task of a parallel section: called once for each index in [0, task_count).
using ParallelTask = std::function<void(uint32_t task)>;

/// Runs `task(i)` for every i in [0, task_count), possibly concurrently and in any order, and
/// returns once every call has returned. Calling them one after the other on the calling
/// thread is a valid ParallelFor.
using ParallelFor = std::function<void(uint32_t task_count, const ParallelTask& task)>;

/// A fixed set of std::thread workers that run ParallelFor sections together with the calling
/// thread. run() may be called from one thread at a time. Workers sleep between sections.
class WorkerPool {
 public:
  /// `threads` counts the calling thread: 0 or 1 starts no worker (run() is then a plain loop),
  /// n starts n - 1 workers. At most 256.
  explicit WorkerPool(uint32_t threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Threads that run a section, the caller included.
  uint32_t threads() const;
  /// Runs the tasks on the workers and the calling thread; returns when all have run (the
  /// calling thread spins up to 200 us on the workers' last tasks before it sleeps). Does not
  /// allocate. May be called from several threads at once: one section at a time uses the
  /// workers, and a caller that finds them busy runs its own tasks on its own thread.
  void run(uint32_t task_count, const ParallelTask& task);

 private:
  struct Shared;
  std::unique_ptr<Shared> shared_;
};

}  // namespace si
