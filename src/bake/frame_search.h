// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The automatic mode's frame search: per clip, the fewest frames whose error on a fixed vertex
// subset meets the tolerance, on a uniform grid (a rate) or placed at the clip's keys (each key
// interval divided for its own error); then, from the whole mesh's measurement, a denser choice
// where it still misses.
#include <cstdint>
#include <vector>

#include "si/bake/animation_baker.h"

namespace si::detail {

/// One clip's frames as the search chose them.
struct FrameChoice {
  FrameInterpolation interpolation = FrameInterpolation::kLinear;
  bool at_keys = false;     ///< Placed at the keys (else a uniform grid at rate_hz).
  double rate_hz = 0.0;     ///< The grid's rate; for key placement, frames / duration.
  FramePlan frames;
  double subset_error = 0.0;  ///< Max error on the subset at the frame intervals' midpoints.
  /// What the search aimed for: the tolerance, or 1.1 x the format's floor where that is
  /// above it (half floats). Refining past it cannot help.
  double target = 0.0;
  /// Key placement: keyBreakpoints() and the pieces of each key interval.
  std::vector<double> breakpoints;
  std::vector<uint32_t> pieces;
  /// Grid: whether a higher candidate rate exists; keys: whether some interval may still be
  /// divided further.
  bool can_refine = false;
};

/// Whether `b` is the better choice than `a` for `target`: one that meets it beats one that
/// does not (subset errors); then fewer frames; then the smaller error (a tie keeps `a`).
bool betterChoice(const FrameChoice& b, const FrameChoice& a, double target);

class FrameSearch {
 public:
  /// `desc` resolved; `gpu_mesh` the mesh with the vertex format's weights; `subset` the
  /// vertices every trial measures (searchVertices(), chosen once on the source mesh).
  FrameSearch(const Character& character, const BakeDesc& desc, const SkinnedMesh& gpu_mesh,
              const std::vector<uint32_t>& subset);

  /// The fewer frames of the grid's lowest rate and of the key placement that meet the
  /// target on the subset (the tolerance, or 1.1 x the format's floor where the format cannot
  /// reach it); the smaller error when neither does.
  Status choose(const Clip& clip, FrameInterpolation interpolation, FrameChoice* out) const;

  /// After the whole mesh's measurement (`interval_errors` per frame interval of
  /// choice->frames) missed choice->target: denser frames where it missed. False when nothing
  /// is left to refine (the highest rate, every interval at its limit).
  bool refine(const Clip& clip, const std::vector<double>& interval_errors,
              FrameChoice* choice) const;

 private:
  Status gridChoice(const Clip& clip, FrameInterpolation interpolation, double target,
                    FrameChoice* out) const;
  Status keyChoice(const Clip& clip, FrameInterpolation interpolation, double target,
                   FrameChoice* out) const;
  Status trial(const Clip& clip, FrameInterpolation interpolation, const FramePlan& frames,
               double* error, std::vector<double>* interval_errors) const;
  std::vector<uint32_t> maxPieces(const std::vector<double>& breakpoints) const;

  const Character& character_;
  const BakeDesc& desc_;
  SkinnedMesh search_mesh_, search_gpu_mesh_;
  std::vector<uint32_t> search_vertices_;  // Every vertex of search_mesh_.
  std::vector<double> candidates_;         // Grid rates tried, lowest first.
  double shell_ = 0.0;
  double tolerance_ = 0.0;
};

}  // namespace si::detail
