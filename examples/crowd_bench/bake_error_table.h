// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's speed-against-error table: each bake configuration (format, rate, joint stride,
// interpolation) of the character, drawn on the field by one path, its GPU time beside the
// bake's measured error.
#include <cstdio>
#include <string>

#include "crowd_bench/bench_scene.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// Prints the table (and CSV rows "error") for `instances` characters drawn by `path` with
/// `lod`; `renderer` (initialised, no character yet, or character 0 to be replaced) draws each
/// configuration's palette. `quick` leaves out the automatic rates. Appends each row's
/// "max error, GPU ms, label" to `plot_data` for the plot.
Status bakeErrorTable(Setup& setup, Renderer& renderer, const Character& character,
                      uint32_t instances, const std::string& path, const LodChoice& lod,
                      bool quick, std::FILE* csv, std::string* plot_data);

}  // namespace si::bench
