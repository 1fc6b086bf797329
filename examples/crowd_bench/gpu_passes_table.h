// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench --gpu-passes: each row's GPU time per pass (si/gl/gpu_passes.h), read a frame
// late so that no frame waits for it, with an estimate of the bytes each per-instance pass moves
// and the bandwidth that implies.
#include <cstdint>
#include <cstdio>
#include <deque>
#include <map>
#include <utility>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// A row's pass times: add() each measured draw's ticket after the draw, with the frame it
/// belongs to (it reads the tickets the GPU is past, never waiting), finish() once the frames
/// are done (it waits for the rest).
class PassCollector {
 public:
  explicit PassCollector(const Renderer& renderer) : renderer_(renderer) {}
  void add(uint64_t ticket, uint32_t frame);
  /// Into `row`: the medians over the frames (each the sum of its draws) by pass (si::GpuPass
  /// order) and of their totals (empty when no draw had a ticket), the draws whose times were
  /// read and those already there at the next draw (read a frame late, no wait).
  void finish(Row* row);

 private:
  bool readFront(bool wait);
  const Renderer& renderer_;
  std::deque<std::pair<uint64_t, uint32_t>> pending_;  // Ticket, frame.
  std::vector<std::pair<GpuPassTimes, uint32_t>> done_;
  uint32_t read_late_ = 0;
};

/// Prints the pass table of `rows` (those with pass times) and writes its CSV (`csv_path`).
void printPassTable(const std::vector<Row>& rows, const char* csv_path);

}  // namespace si::bench
