// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// si-bake --cast: the memory budget of a whole cast, per character and in total, for every
// palette format and interpolation at the tolerance.
#include <cstdio>
#include <string>
#include <vector>

#include "si/bake/bake_desc.h"
#include "si/core/character.h"

namespace si_bake {

struct CastMember {
  std::string name;
  si::Character character;
};

/// Bakes every member with `base` (automatic rates unless it says otherwise) in each format
/// and interpolation, once with frames on a uniform grid (FramePlacement::kGrid) and once with
/// the default placement (kFewer), and prints one row per (character, format, interpolation)
/// with both side by side: frames, bytes, max error as a fraction of the height, whether every
/// clip met the tolerance, bake time and peak memory (MiB, where the system reports it); then
/// the cast's totals. A bake a character refuses (the rotation format with scaled joints) prints
/// its reason instead. Returns false when no bake succeeded.
bool printCastTable(std::FILE* f, const std::vector<CastMember>& cast, const si::BakeDesc& base);

}  // namespace si_bake
