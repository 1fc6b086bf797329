// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// What the shader computes from an instance's records, on the CPU in float: the skinning
/// matrix of a palette slot for an InstanceRecord (frames interpolated, crossfade blended) and,
/// with layered animation, for its LayerRecord over the crowd's masks. The CPU baselines draw
/// with it; the tests compare the GPU with it.

#include <cstdint>

#include <glm/glm.hpp>

#include "si/core/baked_palette.h"
#include "si/core/layer_mask.h"
#include "si/core/span.h"
#include "si/crowd/instance_record.h"

namespace si {

/// Palette slot `slot`'s matrix for `record`: clip A's frames interpolated, crossfaded towards
/// clip B by the record's weight. The record's frames must lie inside the palette.
glm::mat4 emulateRecordMatrix(const BakedPalette& palette, const InstanceRecord& record,
                              uint32_t slot);

/// The morph target weights the shader computes for `record` (si_morph.glsl's siMorphWeight):
/// clip A's interpolated (si::emulateMorphWeights), crossfaded towards clip B's by the record's
/// weight. `out` holds palette.layout.morph_target_count weights (kCountMismatch otherwise).
/// The base record's clips alone: emulateLayeredMorphWeights() adds the overlay.
Status emulateRecordMorphWeights(const BakedPalette& palette, const InstanceRecord& record,
                                 Span<float> out);

/// The same with the instance's overlay (si_morph.glsl's siMorphLayerWeight): where `layer`'s
/// weight is above 0 and its mask (an index into `masks`, CrowdManager::layerMasks()) moves a
/// target, the record's weight mixed towards the overlay clip's (its frames interpolated) by
/// the overlay's weight. A mask index past `masks` reads as no overlay.
Status emulateLayeredMorphWeights(const BakedPalette& palette, const InstanceRecord& record,
                                  const LayerRecord& layer, Span<const LayerMask> masks,
                                  Span<float> out);

/// The same with a 2D blend's extra layers (the compose pass's weights, layer_compose.glsl):
/// where `layer` has kLayerExtrasBit and `extras` holds the instance's kExtraLayerRecords
/// (CrowdView::extraLayerRecords), each target of `layer`'s mask mixed towards the overlay
/// clip's weight by the overlay's weight, then towards each extra layer's clip's by its weight,
/// in turn: the chain of emulateLayeredChain, whose layer weights make each clip's share of a
/// blend (si::BlendPoint::chain). Otherwise as above.
Status emulateLayeredMorphWeights(const BakedPalette& palette, const InstanceRecord& record,
                                  const LayerRecord& layer, Span<const LayerRecord> extras,
                                  Span<const LayerMask> masks, Span<float> out);

/// The same with the instance's overlay: where `layer`'s weight is above 0 and its mask (an
/// index into `masks`, CrowdManager::layerMasks()) holds the slot, emulateLayeredMatrix() of
/// the record's matrices and the overlay's (its frames interpolated) at the slot and its
/// anchor; otherwise emulateRecordMatrix(). A mask index past `masks` reads as no overlay.
glm::mat4 emulateLayeredRecordMatrix(const BakedPalette& palette, const InstanceRecord& record,
                                     const LayerRecord& layer, Span<const LayerMask> masks,
                                     uint32_t slot);

/// The same with a 2D blend's extra layers: where `layer` has kLayerExtrasBit and `extras`
/// holds the instance's kExtraLayerRecords (CrowdView::extraLayerRecords), the overlay and
/// then each extra layer composed on `layer`'s mask (emulateLayeredChain); otherwise as above.
glm::mat4 emulateLayeredRecordMatrix(const BakedPalette& palette, const InstanceRecord& record,
                                     const LayerRecord& layer, Span<const LayerRecord> extras,
                                     Span<const LayerMask> masks, uint32_t slot);

}  // namespace si
