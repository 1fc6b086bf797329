// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The per-instance record the vertex shader reads from the instance uniform block with
/// gl_InstanceID: 80 bytes in std140 (and std430), crossfade included. Its GLSL twin is
/// `SiInstance` in the installed include's si_instance_record.glsl; static_asserts pin the C++
/// offsets and the render tests compare them with the GLSL layout by GL introspection.
///
/// | bytes | GLSL | content |
/// | --- | --- | --- |
/// | 0-47 | `vec4 world_rows[3]` | rows of the 3x4 camera-relative world matrix (rotation * scale, translation) |
/// | 48-63 | `uvec4 frames` | x, y: texel of clip A's frame and next frame (clip first texel + frame * frame stride); z, w: the same for clip B |
/// | 64-79 | `uvec4 blend` | x: fraction A, y: fraction B (floats in [0, 1] as bits, with the si::IntervalMode in bits 30-31: si::packFraction), z: weight of B (float bits, in [0, 1]); w: appearance: tint RGB8 (R in the low byte) and, in the high byte, the custom texture layer select (0: none; k: layer k - 1) |
///
/// Without a crossfade, B repeats A and the weight is 0. The classic layout (a vec4 color and
/// one clip) is also 80 bytes; packing the color into 32 bits is what makes room for clip B, so
/// the crossfade costs no instances per draw: floor(64 KiB / 80 B) = 819.

#include <cstddef>
#include <cstdint>

namespace si {

/// One instance as the shader sees it (std140, 80 bytes).
struct InstanceRecord {
  float world_rows[3][4];  ///< Camera-relative world matrix rows.
  uint32_t frames[4];      ///< Frame texel A, next texel A, frame texel B, next texel B.
  uint32_t blend[4];       ///< Fraction words A and B (si::packFraction), weight B (float bits),
                           ///< appearance (si::packAppearance).
};
static_assert(sizeof(InstanceRecord) == 80, "std140 record is 80 bytes");
static_assert(offsetof(InstanceRecord, frames) == 48, "std140 offset of frames");
static_assert(offsetof(InstanceRecord, blend) == 64, "std140 offset of blend");

/// Layers of an application's custom texture array an instance can select (the record's
/// appearance word holds the select in 8 bits; 0 is none).
inline constexpr uint32_t kMaxCustomLayers = 255;

/// The record's appearance word: tint RGB (R in the low byte; the color's alpha is not stored)
/// and the custom layer select in the high byte.
inline constexpr uint32_t packAppearance(uint8_t r, uint8_t g, uint8_t b, uint8_t custom_layer) {
  return uint32_t(r) | (uint32_t(g) << 8) | (uint32_t(b) << 16) | (uint32_t(custom_layer) << 24);
}

/// Size of InstanceRecord in bytes (its std140 array stride).
inline constexpr uint32_t kInstanceRecordSize = sizeof(InstanceRecord);

}  // namespace si
