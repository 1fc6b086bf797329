// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// WorkerPool: workers wait for a new section (a generation number under a mutex), then take
// task indices from one atomic counter, as the calling thread does; the caller returns once
// every task of the section has finished.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "si/crowd/parallel_for.h"

namespace si {

namespace {
// How long a caller waits on the workers' last tasks without sleeping.
constexpr int kSpinMicroseconds = 200;
// A spinning thread's hint to the core (x86's pause: the sibling thread runs meanwhile).
inline void cpuRelax() {
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
  __builtin_ia32_pause();
#endif
}
}  // namespace

struct WorkerPool::Shared {
  std::mutex section;  // Held by the caller whose section the workers run.
  std::mutex mutex;
  std::condition_variable wake;      // Workers: a new section or the end.
  std::condition_variable finished;  // The caller: the section's last task finished.
  uint64_t generation = 0;           // Sections started; guarded by mutex.
  bool stop = false;
  const ParallelTask* task = nullptr;
  uint32_t task_count = 0;
  // The section's generation (high 32 bits) and next task index (low 32 bits): a worker that
  // woke for an old section never takes a task of the next one.
  std::atomic<uint64_t> next{0};
  std::atomic<uint32_t> done{0};  // Tasks finished in this section.
  std::vector<std::thread> workers;

  // Takes and runs tasks of section `gen` until none is left; true if this thread finished the
  // section's last task.
  bool drain(const ParallelTask& t, uint32_t count, uint32_t gen) {
    bool last = false;
    uint64_t v = next.load(std::memory_order_acquire);
    for (;;) {
      if (uint32_t(v >> 32) != gen || uint32_t(v) >= count) return last;
      if (!next.compare_exchange_weak(v, v + 1, std::memory_order_acq_rel)) continue;
      t(uint32_t(v));
      last = done.fetch_add(1, std::memory_order_acq_rel) + 1 == count;
      v = next.load(std::memory_order_acquire);
    }
  }

  void workerLoop() {
    uint64_t seen = 0;
    for (;;) {
      const ParallelTask* t;
      uint32_t count;
      {
        std::unique_lock<std::mutex> lock(mutex);
        wake.wait(lock, [&] { return stop || generation != seen; });
        if (stop) return;
        seen = generation;
        t = task;
        count = task_count;
      }
      if (drain(*t, count, uint32_t(seen))) {
        std::lock_guard<std::mutex> lock(mutex);  // Orders the notify after the caller's wait.
        finished.notify_one();
      }
    }
  }
};

WorkerPool::WorkerPool(uint32_t threads) : shared_(std::make_unique<Shared>()) {
  const uint32_t n = std::min(std::max(threads, 1u), 256u);
  for (uint32_t i = 1; i < n; ++i)
    shared_->workers.emplace_back([s = shared_.get()] { s->workerLoop(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(shared_->mutex);
    shared_->stop = true;
  }
  shared_->wake.notify_all();
  for (std::thread& t : shared_->workers) t.join();
}

uint32_t WorkerPool::threads() const {
  return uint32_t(shared_->workers.size()) + 1;
}

void WorkerPool::run(uint32_t task_count, const ParallelTask& task) {
  Shared& s = *shared_;
  if (task_count == 0) return;
  // One section at a time uses the workers; a caller on another thread meanwhile (views
  // selecting in parallel) runs its own tasks, rather than waiting or sharing the section.
  std::unique_lock<std::mutex> section(s.section, std::defer_lock);
  if (s.workers.empty() || task_count == 1 || !section.try_lock()) {
    for (uint32_t i = 0; i < task_count; ++i) task(i);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(s.mutex);
    s.task = &task;
    s.task_count = task_count;
    ++s.generation;
    s.done.store(0, std::memory_order_relaxed);
    s.next.store(uint64_t(uint32_t(s.generation)) << 32, std::memory_order_release);
  }
  s.wake.notify_all();
  s.drain(task, task_count, uint32_t(s.generation));
  // Workers may still run the last tasks: wait for them, spinning on this thread for up to
  // kSpinMicroseconds before it sleeps (sections are short; a sleeping caller wakes tens of
  // microseconds after the last task ends). On the H200's host the spin took 1,000 live poses
  // of 60 joints in one setLivePoses from 0.195-0.207 to 0.154-0.169 ms (docs/performance.md,
  // "Live poses: the draw's copy on the crowd's workers").
  const auto until =
      std::chrono::steady_clock::now() + std::chrono::microseconds(kSpinMicroseconds);
  for (uint32_t spin = 1;; ++spin) {
    if (s.done.load(std::memory_order_acquire) == task_count) return;
    if (spin % 256 == 0 && std::chrono::steady_clock::now() >= until) break;
    cpuRelax();
  }
  std::unique_lock<std::mutex> lock(s.mutex);
  s.finished.wait(lock, [&] { return s.done.load(std::memory_order_acquire) == task_count; });
}

}  // namespace si
