// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Counts heap allocations while g_counting is set, by replacing the global operator new and
// delete: include it in exactly one source file of a test binary. GCC cannot see that the
// replaced operator new and delete pair malloc with free.
#include <atomic>
#include <cstdlib>
#include <new>

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
static std::atomic<bool> g_counting{false};
static std::atomic<size_t> g_allocations{0}, g_allocated_bytes{0};
void* operator new(size_t n) {
  if (g_counting) {
    ++g_allocations;
    g_allocated_bytes += n;
  }
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
