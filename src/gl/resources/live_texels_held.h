// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What a copy of a crowd's live poses holds (the palette texture's live rows, the baselines'
// palette copy, the GPU-driven path's slot table): which crowd and which live version, and so
// what to write to bring it up to date. One crowd's copy goes on from the version it holds;
// another crowd's starts over. No GL.

#include <cstdint>

#include "si/crowd/crowd_export.h"

namespace si::detail {

class LiveTexelsHeld {
 public:
  /// Whether the copy lacks crowd `identity`'s current live poses (`live`); if so, the span of
  /// livePoseTexels() to write, in texels (livePoseTexelsChangedSince: those written since the
  /// version held for the same crowd, all of them for another; not looked for when `first` is
  /// null: a copy written whole), and the copy counts as holding them from now on (forget()
  /// after a write that failed).
  bool update(const CrowdExport& live, uint64_t identity, uint32_t* first = nullptr,
              uint32_t* count = nullptr) {
    const uint64_t version = live.livePoseVersion();
    if (identity == identity_ && version == version_) return false;
    if (first != nullptr)
      live.livePoseTexelsChangedSince(identity == identity_ ? version_ : 0, first, count);
    identity_ = identity;
    version_ = version;
    return true;
  }
  /// The copy holds nothing (made again, or its write failed).
  void forget() { identity_ = version_ = 0; }

 private:
  uint64_t identity_ = 0, version_ = 0;
};

}  // namespace si::detail
