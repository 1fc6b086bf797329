// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The layer compose pass: one invocation per (record of a batch, masked index of the row
// stride) composes the record's overlay on that masked palette slot (siLayeredJointRows, the
// chain walk the vertex shaders would otherwise repeat per vertex and influence) into the rows
// buffer (layer_compose.glsl). Records at weight 0, and indices past their mask's count, write
// nothing: the vertex shaders never read them. SI_MOTION_VECTORS: the previous records' too.
// drawCrowd's: one row of groups per batch of the compose table the renderer wrote into the
// ring (layer_compose_pass.h, writeComposeBatches), the records read from the ring. With
// SI_GPU_DRIVEN: the cull pass's records (and previous records) by visible index, as many as it
// counted visible, composed record = visible index.
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
layout(std430, binding = 26) writeonly buffer SiComposedOut { vec4 si_composed_out[]; };
#ifdef SI_MOTION_VECTORS
layout(std430, binding = 27) writeonly buffer SiComposedPreviousOut {
  vec4 si_composed_previous_out[];
};
#endif
#ifdef SI_GPU_DRIVEN
layout(location = 5) uniform uint u_instances;  // Bounds the visible count.
// 2D blends: the cull pass's extra layer records, 2 per visible index, from this index of its
// layer records (and of its previous ones).
layout(location = 6) uniform uint u_extras;
#ifdef SI_MOTION_VECTORS
layout(location = 7) uniform uint u_previous_extras;
#endif
uvec4 siExtraLayer(uint record, uint k, bool previous) {
#ifdef SI_MOTION_VECTORS
  if (previous) return si_previous_layers[u_previous_extras + 2u * record + k];
#endif
  return si_layers[u_extras + 2u * record + k];
}
#else
// The frame's region of the ring (ring_words.glsl): the batch table, the records, the layer
// records; with SI_MOTION_VECTORS the previous indices and records (previous_index.glsl).
#include "ring_words.glsl"
#ifdef SI_MOTION_VECTORS
#include "previous_index.glsl"
#endif
layout(location = 5) uniform uint u_table;  // The first batch entry of this dispatch.
// The previous layer records' words after the current ones'.
layout(location = 6) uniform uint u_previous_layer_shift;
// 2D blends: the first word of the extra layer records (2 per composed record; 0: none), and of
// the previous ones.
layout(location = 7) uniform uint u_extra_word;
#ifdef SI_MOTION_VECTORS
layout(location = 10) uniform uint u_previous_extra_word;
#endif
// Extra layer record `k` of composed record `record` (the previous ones: `previous`).
uvec4 siExtraLayer(uint record, uint k, bool previous) {
#ifdef SI_MOTION_VECTORS
  if (previous) return si_ring[u_previous_extra_word + 2u * record + k];
#endif
  return si_ring[u_extra_word + 2u * record + k];
}
#endif

// Composes record `inst`'s overlay `layer` (and with kLayerExtrasBit composed record
// `record`'s extra layers; `previous`: the previous ones) on masked index `k` into `rows` at
// vec4 `at`.
#define SI_COMPOSE(inst, layer, record, previous, k, rows, at)                       \
  {                                                                                  \
    int slot = siComposedSlot(layer, k);                                             \
    if (slot >= 0) {                                                                 \
      vec4 r0, r1, r2;                                                               \
      bool extras = (layer.w & 0x80000000u) != 0u;                                   \
      uvec4 e1 = extras ? siExtraLayer(record, 0u, previous) : uvec4(0u);            \
      uvec4 e2 = extras ? siExtraLayer(record, 1u, previous) : uvec4(0u);            \
      siLayeredChainRows(inst, layer, e1, e2, uint(slot), r0, r1, r2);               \
      rows[at] = r0;                                                                 \
      rows[at + 1u] = r1;                                                            \
      rows[at + 2u] = r2;                                                            \
    }                                                                                \
  }

void main() {
  uint stride = siComposeStride();
#ifdef SI_GPU_DRIVEN
  // One flat pass over the visible records: composed record = visible index.
  uint g = siFlatInvocation();
  uint i = g / stride;
  if (i >= min(si_visible_count, u_instances)) return;
  uint k = g - i * stride;
  uint at = g * 3u;
  SI_COMPOSE(si_instances[i], si_layers[i], i, false, k, si_composed_out, at);
#ifdef SI_MOTION_VECTORS
  SI_COMPOSE(si_previous_instances[i], si_previous_layers[i], i, true, k,
             si_composed_previous_out, at);
#endif
#else
  // A row of groups per batch: its records' word, its layer records' word, its record count,
  // its first composed record.
  uvec4 batch = si_ring[u_table + gl_WorkGroupID.y];
  uint g = gl_WorkGroupID.x * 64u + gl_LocalInvocationIndex;
  uint i = g / stride;
  if (i >= batch.z) return;
  uint k = g - i * stride;
  uint at = ((batch.w + i) * stride + k) * 3u;
  uint record = batch.x + 5u * i, layer = batch.y + i;
  SiInstance inst = siRingRecord(record);
  SI_COMPOSE(inst, si_ring[layer], batch.w + i, false, k, si_composed_out, at);
#ifdef SI_MOTION_VECTORS
  SI_COMPOSE(siPreviousRecord(batch.w + i, inst), si_ring[layer + u_previous_layer_shift],
             batch.w + i, true, k, si_composed_previous_out, at);
#endif
#endif
}
