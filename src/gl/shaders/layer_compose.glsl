// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Composed layers, after si_skinning.glsl with SI_LAYERS: the compose pass
// (layer_compose.comp.glsl) runs siLayeredJointRows once per frame for each overlaid record's
// masked palette slots, and the vertex shaders read those rows instead of walking each
// influence's chain per vertex (src/gl/paths/layer_compose_pass.h).
// The compose table (storage binding 23; si::detail::layerComposeTable): [0] palette slots,
// [1] the row stride (the most masked slots of any mask), [2] the mask count, [3] the composed
// morph targets (past the highest any mask holds); then per mask each slot's index among the
// mask's masked slots (-1 outside it); then per mask its masked slots in order (-1 past its
// count).
// The rows (storage binding 26; the previous records' at 27): per composed record 3 vec4 per
// masked index (index k's at 3 * k), then its weight of each composed morph target, four to a
// vec4 (si::detail::ComposeShape), so the vertices read one weight instead of interpolating
// every layer's clip per target (with SI_MORPH_TARGETS: si_morph.glsl). A composed record is an instance:
// the GPU-driven cull pass's visible index, or drawCrowd's record of the view, which each drawn
// slot names (SI_COMPOSED_BY_SLOT: storage binding 30), so an instance is composed once however
// many sub-meshes it wears.
#ifndef SI_LAYER_COMPOSE_GLSL
#define SI_LAYER_COMPOSE_GLSL
layout(std430, binding = 23) readonly buffer SiComposeTable { int si_compose_table[]; };

uint siComposeStride() { return uint(si_compose_table[1]); }
uint siComposedMorphTargets() { return uint(si_compose_table[3]); }
// vec4s per composed record: its rows, then its weights.
uint siComposedRecordSize() { return 3u * siComposeStride() + (siComposedMorphTargets() + 3u) / 4u; }
// Invocations of the compose pass per record (si::detail::ComposeShape::lanes).
uint siComposeLanes() { return max(siComposeStride(), min(siComposedMorphTargets(), 1u)); }

// Whether `layer` composes anything: a weight above 0, or a 2D blend's extra layers (bit 31).
bool siLayerDrawn(uvec4 layer) { return (layer.w & 0x8000FFFFu) != 0u; }

// The index of palette slot `joint` among the masked slots of `layer`'s mask; -1 outside the
// mask or with nothing composed (the base rows then, as siLayeredJointRows gives).
int siComposedIndex(uvec4 layer, uint joint) {
  if (!siLayerDrawn(layer)) return -1;
  return si_compose_table[4u + siLayerMask(layer) * uint(si_compose_table[0]) + joint];
}

// The palette slot of masked index `k` of `layer`'s mask; -1 past its count or with nothing
// composed.
int siComposedSlot(uvec4 layer, uint k) {
  if (!siLayerDrawn(layer)) return -1;
  uint slots = uint(si_compose_table[0]), masks = uint(si_compose_table[2]);
  if (k >= siComposeStride()) return -1;  // A lane that composes weights only.
  return si_compose_table[4u + masks * slots + siLayerMask(layer) * siComposeStride() + k];
}

// The rows and the previous ones: the compose pass writes them, the skinning reads them
// (SI_COMPOSED_READ).
#ifdef SI_COMPOSED_READ
#define SI_COMPOSED_ACCESS readonly
#else
#define SI_COMPOSED_ACCESS writeonly
#endif
layout(std430, binding = 26) SI_COMPOSED_ACCESS buffer SiComposedRows { vec4 si_composed[]; };
#ifdef SI_PREVIOUS_RECORDS
layout(std430, binding = 27) SI_COMPOSED_ACCESS buffer SiComposedPreviousRows {
  vec4 si_composed_previous[];
};
#endif

#ifdef SI_COMPOSED_READ
#ifdef SI_COMPOSED_BY_SLOT
layout(std430, binding = 30) readonly buffer SiComposedSlots { uint si_composed_slots[]; };
// drawCrowd: the composed record of slot `slot` (the batch's first slot plus the place).
uint siComposedRecord(uint slot) { return si_composed_slots[slot]; }
#endif
vec4 siComposedRow(bool previous, uint at) {
#ifdef SI_PREVIOUS_RECORDS
  if (previous) return si_composed_previous[at];
#endif
  return si_composed[at];
}

// The rows of palette slot `joint` from composed record `record` (its previous rows with
// `previous`) where the overlay's mask holds it; elsewhere siInstanceJointRows.
void siComposedJointRows(SiInstance inst, uvec4 layer, uint record, bool previous, uint joint,
                         out vec4 r0, out vec4 r1, out vec4 r2) {
  // One if-else, no early return: NVIDIA's compiler made the vertex shaders 5-10 % slower with
  // one (docs/performance.md, "Duplicates merged").
  int c = siComposedIndex(layer, joint);
  if (c < 0) {
    siInstanceJointRows(inst, joint, r0, r1, r2);
  } else {
    uint at = record * siComposedRecordSize() + uint(c) * 3u;
    r0 = siComposedRow(previous, at);
    r1 = siComposedRow(previous, at + 1u);
    r2 = siComposedRow(previous, at + 2u);
  }
}

// siSkinLayered with composed record `record`'s rows (the previous records' when `previous`):
// masked influences read three rows, the others fetch and interpolate the palette as siSkin.
void siSkinComposed(SiInstance inst, uvec4 layer, uint record, bool previous, uvec4 joints,
                    vec4 weights, out vec4 m0, out vec4 m1, out vec4 m2) {
  SI_SKIN_SUM(joints, weights, siComposedJointRows(inst, layer, record, previous, joint, r0, r1, r2))
}

#ifdef SI_MORPH_TARGETS
// Target `target`'s weight as the compose pass composed it for record `record` (its previous
// one with `previous`) into `w`: false, reading nothing, where it composed none (no layer drawn,
// or a target past those the masks hold: siMorphLayerWeight's then, the base clips').
bool siComposedMorphWeight(uvec4 layer, uint record, bool previous, uint target, out float w) {
  w = 0.0;
  if (!siLayerDrawn(layer) || target >= siComposedMorphTargets()) return false;
  uint at = record * siComposedRecordSize() + 3u * siComposeStride() + (target >> 2u);
  w = siComposedRow(previous, at)[int(target & 3u)];
  return true;
}
#endif
#endif
#endif
