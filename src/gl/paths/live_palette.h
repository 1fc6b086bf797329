// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The baselines' palette with a crowd's live poses (CrowdManager::setLivePose): the CPU reads
// a record's frames from the palette's texels by index (si::emulateRecordMatrix), so a record
// naming a live frame needs the live texels after the palette's, as the palette texture holds
// them. A copy of the palette made once per palette, whose live tail is rewritten with the
// frames written since it last held the crowd's (all of them for another crowd). No GL.

#include <cstdint>

#include "gl/resources/live_texels_held.h"
#include "si/core/baked_palette.h"
#include "si/crowd/crowd_manager.h"

namespace si::detail {

class LivePalette {
 public:
  /// `palette` itself for a crowd without room for live poses; else the copy with the crowd's
  /// live texels after the palette's, valid until the next call.
  const BakedPalette& of(const BakedPalette& palette, const CrowdManager& crowd);

 private:
  BakedPalette copy_;
  const BakedPalette* source_ = nullptr;
  size_t palette_bytes_ = 0;  // The palette's own texel bytes (the live tail after them).
  LiveTexelsHeld held_;       // The crowd and live version the tail holds.
};

}  // namespace si::detail
