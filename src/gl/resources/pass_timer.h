// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// GPU time per pass (RendererDesc::measure_gpu_passes, si/gl/gpu_passes.h): each draw that
// returns stats takes one of Renderer::kGpuPassTickets sets of timestamp queries, stamps its
// start and the end of each pass, and is read later by its ticket without waiting.

#include <glad/gl.h>

#include <array>
#include <cstdint>
#include <vector>

#include "gl/resources/gpu_timer.h"
#include "si/core/status.h"
#include "si/gl/gpu_passes.h"

namespace si::detail {

class PassTimer {
 public:
  /// Stamps a set holds: a draw of more passes (the compute path's chunks) counts the time
  /// past the last free stamp in the pass that ends it.
  static constexpr uint32_t kStamps = 48;

  /// Deletes the queries.
  void release();
  /// Starts a draw's set (the oldest of `sets`, reused; the queries are made at the first
  /// draw that asks) with its first stamp, and gives its ticket.
  uint64_t begin(uint32_t sets);
  /// Ends pass `pass` of the draw begun: the time since the last stamp is the pass's. Nothing
  /// outside a draw.
  void mark(GpuPass pass);
  /// Ends the draw (the time since the last stamp counted in `rest`): marks stop until begin().
  void end(GpuPass rest);
  /// The times of the draw that took `ticket` (Renderer::readGpuPasses' rules).
  Status read(uint64_t ticket, GpuPassTimes* out) const;

 private:
  // Stamps the active set's next query as the end of `pass`.
  void stamp(GpuPass pass);
  struct Set {
    uint64_t ticket = 0;
    uint32_t stamps = 0;
    std::array<GpuPass, kStamps> passes{};  // The pass each stamp after the first ends.
  };
  std::vector<GLuint> queries_;  // kStamps per set.
  std::vector<Set> sets_;
  uint64_t issued_ = 0;    // Tickets given: the last one's number.
  Set* active_ = nullptr;  // The set of the draw between begin() and end().
};

}  // namespace si::detail
