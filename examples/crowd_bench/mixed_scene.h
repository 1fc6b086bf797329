// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's mixed scene (--mix): the field shared by several character kinds (the embedded
// character and glTF models), each with its own palette and crowd, drawn by one renderer
// (Renderer::addCharacter, each crowd with its CharacterId) and, side by side in the same run,
// by one renderer per kind.
#include <cstdio>
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"
#include "si/core/baked_palette.h"
#include "si/core/character.h"

namespace si::bench {

struct MixedKind {
  std::string name;
  Character character;
  BakedPalette palette;
};

/// Kind 0: `main` with `main_palette` (copied); then each glTF file imported, given an LOD
/// chain (si::buildLodChain) when `lod_chain`, and baked (automatic rates, or 30 Hz with
/// `quick`).
Status loadMixedKinds(const Character& main, const BakedPalette& main_palette,
                      const std::vector<std::string>& files, bool lod_chain, bool quick,
                      std::vector<MixedKind>* out);

struct MixedRow : Row {  // Row::scene and lod unused.
  bool one_renderer = true;
};

/// Times `path` on the field of `count` places shared round-robin by `kinds` (each kind's
/// largest extent scaled to the embedded character's height): every crowd updated, then drawn
/// by one renderer holding every kind (`one_renderer`) or by one renderer per kind. Times and
/// counts are summed over the kinds' draws.
Status runMixed(Setup& setup, const std::vector<MixedKind>& kinds, const RendererDesc& desc,
                uint32_t count, const std::string& path, bool one_renderer, MixedRow* row);

/// The mixed table: for each size and path (the baselines only up to `max_baseline`), one
/// renderer against one renderer per kind, side by side, with their ratios; rows to `csv` too.
Status mixedTable(Setup& setup, const std::vector<MixedKind>& kinds, const RendererDesc& desc,
                  const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                  uint32_t max_baseline, std::FILE* csv);

}  // namespace si::bench
