// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The error of layered animation (si/core/layer_mask.h): a base clip with an overlay clip on a
/// mask, as the shader blends them from the palette (emulateLayeredMatrix, float, the vertex
/// format's quantized weights), against the reference blending the local transforms in double
/// (evaluateLayeredPose). Both sampled at the same times; the error is the largest vertex
/// distance, in model units and as a fraction of the character's height.
///
/// Usage:
/// \code
///   si::LayeredErrorReport report;
///   si::Status s = si::measureLayeredError(character, palette, mask, walk, wave, {}, &report);
///   // report.max_error_units, report.max_error_ratio, report.per_weight
/// \endcode

#include <cstdint>
#include <vector>

#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/core/layer_mask.h"
#include "si/core/status.h"

namespace si {

struct LayeredErrorReport {
  struct AtWeight {
    float weight = 0.0f;
    double max_error_units = 0.0;
    double max_error_ratio = 0.0;  ///< Of the character's height.
  };
  std::vector<AtWeight> per_weight;  ///< One per weight measured, in the order given.
  double max_error_units = 0.0;      ///< The largest over every weight and time.
  double max_error_ratio = 0.0;
  float worst_weight = 0.0f;         ///< Where it was.
  double worst_time_seconds = 0.0;   ///< Time from both clips' start.
  uint32_t samples = 0;              ///< Times measured per weight.
};

/// Measures palette clips `base_clip` and `overlay_clip` (indices into palette.clips; the
/// character's clips of the same names are the reference) layered through `mask` at each of
/// `weights` (empty: 0.25, 0.5, 0.75 and 1), both clips started together, at `samples` times
/// spread over the longer clip's duration (0: 64). kInvalidArgument for a null report, a clip
/// index past the palette, a weight outside [0, 1], a mask that fails validate(palette) or a
/// palette not baked from the character (joint count); kNotFound for a palette clip the
/// character does not have.
Status measureLayeredError(const Character& character, const BakedPalette& palette,
                           const LayerMask& mask, uint32_t base_clip, uint32_t overlay_clip,
                           const std::vector<float>& weights, LayeredErrorReport* report,
                           uint32_t samples = 0);

}  // namespace si
