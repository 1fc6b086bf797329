// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The GPU-driven cull passes' counters as their shaders lay them out (shaders/cull_counters.glsl,
// std430 binding 3), in 32-bit words: shared by si::gl's GPU-driven path and si::vk's, which
// clear, read and dispatch from them. No GL here.

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "si/crowd/handle_pool.h"
#include "si/crowd/instance_record.h"

namespace si::detail {

inline constexpr uint32_t kMaxBuckets = 256;
inline constexpr uint32_t kBucketCountWord = 4, kDispatchWord = 4 + 2 * kMaxBuckets;
inline constexpr uint32_t kSkinDispatchWord = kDispatchWord + 4;
inline constexpr uint32_t kThreadBaseWord = kSkinDispatchWord + 4 + kMaxBuckets;
inline constexpr uint32_t kFittedWord = kThreadBaseWord + kMaxBuckets + 1;
inline constexpr uint32_t kImpostorDispatchWord = kFittedWord + kMaxBuckets;
inline constexpr uint32_t kImpostorsDrawnWord = kImpostorDispatchWord + 4;
inline constexpr uint32_t kCounterWords = kImpostorsDrawnWord + 1;
// SiCommands (cull_commands.comp.glsl): 5-word indexed commands, vertex-shader draws from 0 and
// pre-skinned draws from kMaxBuckets, then the impostor quads' 4-word command.
inline constexpr uint32_t kCommandWords = 2 * kMaxBuckets * 5 + 4;
// The impostor quads pass's output (shaders/impostor_quads.comp.glsl): 4 words of 16 bytes.
inline constexpr uint32_t kImpostorQuadBytes = 64;

// Motion vectors: cull.comp.glsl's SiDrawn, a view's drawn record per handle slot (two
// parities): a record, a layer record, a 2D blend's extra layer records and a tag.
inline constexpr size_t kDrawnBytes =
    kInstanceRecordSize + (1 + kExtraLayerRecords) * kLayerRecordSize + 16;

// The handle slots a view's drawn records are made for when `needed` pass the `current` ones:
// room to grow (twice the last) within the handle slots and `max_bytes` of a buffer, at least
// `needed` (the caller refuses what then passes `max_bytes`).
inline uint32_t drawnSlotsToMake(uint32_t needed, uint32_t current, uint64_t max_bytes) {
  const uint64_t fit = max_bytes / (2 * kDrawnBytes);
  const uint32_t room =
      uint32_t(std::min<uint64_t>({uint64_t(2) * current, HandlePool::kMaxSlots, fit}));
  return std::max(needed, room);
}

}  // namespace si::detail
