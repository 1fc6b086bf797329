// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven morph weights (after the culling passes, for the vertex-shader draw): one thread
// per visible instance writes its morph targets' weights, rows of 4 (siMorphLayerWeightRow: the
// record's clips and, with SI_LAYERS, the overlay on its mask), at visible index x rows, so that
// the vertex shader (SI_MORPH_WEIGHTS_IN_STORAGE) reads each entry's weight instead of
// interpolating the palette's frames for every vertex. Without SI_MORPH_TARGETS it does nothing.
#ifdef SI_LAYERS
#define SI_LAYERS_IN_STORAGE  // The cull pass's layer records, by visible index.
#define SI_LAYER_BINDING 18
#endif
#include "si_skinning.glsl"
#include "cull_counters.glsl"
#include "dispatch_index.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 4) readonly buffer SiRecords { SiInstance si_records[]; };
layout(std430, binding = 31) writeonly buffer SiMorphWeightsOut { vec4 si_morph_weights_out[]; };
void main() {
#ifdef SI_MORPH_TARGETS
  uint v = siFlatInvocation();
  if (v >= si_visible_count) return;
  uint rows = (si_morph_info.w + 3u) / 4u;
  SiInstance inst = si_records[v];
#ifdef SI_LAYERS
  uvec4 layer = si_layers[v];
#else
  uvec4 layer = uvec4(0u);
#endif
  for (uint r = 0u; r < rows; ++r) si_morph_weights_out[v * rows + r] = siMorphLayerWeightRow(inst, layer, r);
#endif
}
