// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The GPU-driven cull passes' counters as their shaders lay them out (shaders/cull_counters.glsl,
// std430 binding 3), in 32-bit words: shared by si::gl's GPU-driven path and si::vk's, which
// clear, read and dispatch from them. No GL here.

#include <cstdint>

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

}  // namespace si::detail
