// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The per-instance record the vertex shader reads from the instance uniform block with
/// gl_InstanceID: 80 bytes in std140 (and std430), crossfade included. Its GLSL twin is
/// `SiInstance` in the installed include's si_instance_record.glsl; static_asserts pin the C++
/// offsets, the build checks them against the GLSL declaration's (src/gl/shader_layouts.cpp),
/// and the render tests against each program's by GL introspection.
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

/// Motion vectors: what a previous-record index (CrowdView::previousRecordIndices(),
/// CrowdView::previousRecordIndices()) holds for an instance with no previous record.
inline constexpr uint32_t kNoPreviousRecord = 0xFFFFFFFFu;

/// Layered animation (CrowdManager::playOverlay): the overlay clip an instance plays on a
/// joint mask, as a second record parallel to its InstanceRecord (16 bytes, a uvec4 in std140
/// and std430). Weight 0: no overlay (the shader skips it).
///
/// | word | content |
/// | --- | --- |
/// | 0, 1 | texel of the overlay clip's frame and next frame |
/// | 2 | fraction word (si::packFraction) |
/// | 3 | weight as unorm16 in the low half, the crowd's mask index in bits 16-30; bit 31 set when
/// the instance draws extra layers (kLayerExtrasBit) |
///
/// A 2D blend's third and fourth clips are two more layer records of the same form
/// (CrowdView::extraLayerRecords), composed after this one on its mask, each at its own
/// weight; bit 31 of this record's last word says they are there.
struct LayerRecord {
  uint32_t frames[2] = {0, 0};
  uint32_t fraction = 0;
  uint32_t weight_mask = 0;
};
static_assert(sizeof(LayerRecord) == 16, "std140 layer record is 16 bytes");
inline constexpr uint32_t kLayerRecordSize = sizeof(LayerRecord);

/// A layer record's last word: `weight` in [0, 1] rounded to unorm16, and mask `mask`.
inline uint32_t packLayerWeight(float weight, uint32_t mask) {
  const float w = weight > 0.0f ? (weight < 1.0f ? weight : 1.0f) : 0.0f;
  return uint32_t(w * 65535.0f + 0.5f) | (mask << 16);
}
/// Bit of a layer record's last word set when its instance's extra layer records (a 2D blend's
/// third and fourth clips) hold a weight above 0.
inline constexpr uint32_t kLayerExtrasBit = 1u << 31;
/// Extra layer records per drawn instance (CrowdView::extraLayerRecords).
inline constexpr uint32_t kExtraLayerRecords = 2;

/// Its weight, as the shader reads it.
inline float layerWeight(const LayerRecord& r) { return float(r.weight_mask & 0xFFFFu) / 65535.0f; }
/// Its mask index.
inline uint32_t layerMask(const LayerRecord& r) {
  return (r.weight_mask & ~kLayerExtrasBit) >> 16;
}
/// Whether its instance's extra layer records are drawn.
inline bool layerHasExtras(const LayerRecord& r) {
  return (r.weight_mask & kLayerExtrasBit) != 0;
}

}  // namespace si
