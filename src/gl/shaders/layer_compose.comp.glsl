// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The layer compose pass: one invocation per (record of a batch, masked index of the row
// stride) composes the record's overlay on that masked palette slot (siLayeredJointRows, the
// chain walk the vertex shaders would otherwise repeat per vertex and influence) into the rows
// buffer (layer_compose.glsl), and with SI_MORPH_TARGETS every stride-th of the record's
// composed morph weights after them (siMorphChainWeight: a 2D blend's extra layers move the
// targets there, and only there). Records at weight 0, and indices past their mask's count,
// write nothing: the vertex shaders never read them. SI_MOTION_VECTORS: the previous records'
// too.
// drawCrowd's: one flat pass over the view's records (an instance each, whatever sub-meshes it
// wears), each found at its first drawn slot through the entries the renderer wrote into the
// ring (crowd/composed_places.h), composed record = the view's record. With SI_GPU_DRIVEN: the
// cull pass's records (and previous records) by visible index, as many as it counted visible,
// composed record = visible index.
#ifdef SI_MOTION_VECTORS
#define SI_PREVIOUS_RECORDS
#endif
#define SI_LAYERS
#ifdef SI_GPU_DRIVEN
#define SI_INSTANCES_IN_STORAGE
#define SI_RECORDS_BINDING 4
#define SI_LAYER_BINDING 18
#define SI_PREVIOUS_BINDING 20
#define SI_PREVIOUS_LAYER_BINDING 21
#endif
#include "si_skinning.glsl"
#ifdef SI_GPU_DRIVEN
#include "cull_counters.glsl"
#endif
#include "layer_compose.glsl"
#include "dispatch_index.glsl"
layout(local_size_x = 64) in;
#ifdef SI_GPU_DRIVEN
// x: the instances (bounds the visible count); 2D blends: the cull pass's extra layer records,
// 2 per visible index, from index y of its layer records (z: of its previous ones).
layout(location = 5) uniform uvec3 u_compose;
uvec4 siExtraLayer(uint record, uint k, bool previous) {
#ifdef SI_MOTION_VECTORS
  if (previous) return si_previous_layers[u_compose.z + 2u * record + k];
#endif
  return si_layers[u_compose.y + 2u * record + k];
}
#else
// The frame's region of the ring (ring_words.glsl): the batch table, the records, the layer
// records; with SI_MOTION_VECTORS the previous indices and records (previous_index.glsl).
#include "ring_words.glsl"
#ifdef SI_MOTION_VECTORS
#include "previous_index.glsl"
#endif
// x: the entries' first word (2 words a record: its record's word and its first drawn slot;
// 0xFFFFFFFF drawn nowhere); y: the record count; z: the layer records' first word (a slot's
// layer record at its slot from there); w: the previous layer records' words after the
// current ones'.
layout(location = 5) uniform uvec4 u_compose;
// 2D blends: the first word of the extra layer records (2 per slot; 0: none), and of the
// previous ones.
layout(location = 6) uniform uvec2 u_extra_words;
// Extra layer record `k` of slot `slot` (the previous ones: `previous`).
uvec4 siExtraLayer(uint slot, uint k, bool previous) {
  return si_ring[(previous ? u_extra_words.y : u_extra_words.x) + 2u * slot + k];
}
#endif

// Composes record `inst`'s overlay `layer` (and with kLayerExtrasBit the extra layers at
// `record`: its visible index, or drawCrowd's slot; `previous`: the previous ones) on masked
// index `k` into `rows` at vec4 `at`. The arguments are evaluated inside the block, after its
// `palette_slot`: pass names, not expressions of other locals.
#define SI_COMPOSE(inst, layer, record, previous, k, rows, at)                       \
  {                                                                                  \
    int palette_slot = siComposedSlot(layer, k);                                     \
    if (palette_slot >= 0) {                                                         \
      vec4 r0, r1, r2;                                                               \
      bool extras = (layer.w & 0x80000000u) != 0u;                                   \
      uvec4 e1 = extras ? siExtraLayer(record, 0u, previous) : uvec4(0u);            \
      uvec4 e2 = extras ? siExtraLayer(record, 1u, previous) : uvec4(0u);            \
      siLayeredChainRows(inst, layer, e1, e2, uint(palette_slot), r0, r1, r2);       \
      rows[at] = r0;                                                                 \
      rows[at + 1u] = r1;                                                            \
      rows[at + 2u] = r2;                                                            \
    }                                                                                \
  }

#ifdef SI_MORPH_TARGETS
// Writes the weights of record `inst` with overlay `layer` (and its extra layers at `record`,
// as SI_COMPOSE) of the composed targets lane `k` of `lanes` takes (k, k + lanes, ...) into
// `rows` from vec4 `at`: siMorphChainWeight, si::emulateLayeredMorphWeights.
#define SI_COMPOSE_WEIGHTS(inst, layer, record, previous, k, lanes, rows, at)               \
  if (siLayerDrawn(layer)) {                                                              \
    bool extras = (layer.w & 0x80000000u) != 0u;                                          \
    uvec4 e1 = extras ? siExtraLayer(record, 0u, previous) : uvec4(0u);                   \
    uvec4 e2 = extras ? siExtraLayer(record, 1u, previous) : uvec4(0u);                   \
    for (uint target = k; target < siComposedMorphTargets(); target += lanes)             \
      rows[at + (target >> 2u)][int(target & 3u)] = siMorphChainWeight(inst, layer, e1, e2, target); \
  }
#else
#define SI_COMPOSE_WEIGHTS(inst, layer, record, previous, k, lanes, rows, at)
#endif

void main() {
  uint lanes = siComposeLanes(), size = siComposedRecordSize();
  uint weights = 3u * siComposeStride();  // Where a record's weights start.
#ifdef SI_GPU_DRIVEN
  // One flat pass over the visible records: composed record = visible index.
  uint g = siFlatInvocation();
  uint i = g / lanes;
  if (i >= min(si_visible_count, u_compose.x)) return;
  uint k = g - i * lanes;
  uint at = i * size + 3u * k;
  SI_COMPOSE(si_instances[i], si_layers[i], i, false, k, si_composed, at);
  SI_COMPOSE_WEIGHTS(si_instances[i], si_layers[i], i, false, k, lanes, si_composed,
                     i * size + weights);
#ifdef SI_MOTION_VECTORS
  SI_COMPOSE(si_previous_instances[i], si_previous_layers[i], i, true, k,
             si_composed_previous, at);
  SI_COMPOSE_WEIGHTS(si_previous_instances[i], si_previous_layers[i], i, true, k, lanes,
                     si_composed_previous, i * size + weights);
#endif
#else
  // One flat pass over the view's records: composed record = the view's record.
  uint g = siFlatInvocation();
  uint r = g / lanes;
  if (r >= u_compose.y) return;
  uint k = g - r * lanes;
  uvec4 words = si_ring[u_compose.x + (r >> 1u)];
  uvec2 entry = (r & 1u) == 0u ? words.xy : words.zw;
  if (entry.x == 0xFFFFFFFFu) return;  // Drawn in no batch.
  // Its first drawn slot: its layer records, previous index and extra layers there.
  uint at = r * size + 3u * k, drawn_slot = entry.y, layer = u_compose.z + drawn_slot;
  SiInstance inst = siRingRecord(entry.x);
  SI_COMPOSE(inst, si_ring[layer], drawn_slot, false, k, si_composed, at);
  SI_COMPOSE_WEIGHTS(inst, si_ring[layer], drawn_slot, false, k, lanes, si_composed,
                     r * size + weights);
#ifdef SI_MOTION_VECTORS
  SiInstance prev = siPreviousRecord(drawn_slot, inst);
  SI_COMPOSE(prev, si_ring[layer + u_compose.w], drawn_slot, true, k,
             si_composed_previous, at);
  SI_COMPOSE_WEIGHTS(prev, si_ring[layer + u_compose.w], drawn_slot, true, k, lanes,
                     si_composed_previous, r * size + weights);
#endif
#endif
}
