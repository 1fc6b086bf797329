// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven pre-skinning (after the three culling passes, dispatched indirectly): one thread
// per vertex of every pre-skinned entry, buckets one after another as the command pass laid
// them out; thread g writes ring vertex g (and, for a source with tangents, tangent ring word g).
// SI_LAYERS: each entry's overlay (the cull pass's layer record at storage binding 18) composed
// on its mask (with SI_COMPOSED_LAYERS read from the compose pass's rows).
#ifdef SI_LAYERS
#define SI_LAYERS_IN_STORAGE
#define SI_LAYER_BINDING 18
#endif
#ifdef SI_MOTION_VECTORS  // Also the previous position (siPreSkinPrevious) into the previous ring.
#define SI_PREVIOUS_RECORDS
#define SI_PREVIOUS_IN_STORAGE  // The cull pass's previous (layer) records, by visible index.
#define SI_PREVIOUS_BINDING 20
#define SI_PREVIOUS_LAYER_BINDING 21
#endif
#define SI_SOURCE_BINDING 14
#define SI_LOD_VERTICES_BINDING 15
#include "si_skinning.glsl"
#ifdef SI_COMPOSED_LAYERS  // The compose pass's rows, by visible index.
#define SI_COMPOSED_READ
#include "layer_compose.glsl"
#endif
#define SI_SKINNED_OUT_BINDING 13
#define SI_SKINNED_PREVIOUS_OUT_BINDING 22
#include "pre_skin_common.glsl"
#include "cull_counters.glsl"
#include "dispatch_index.glsl"
layout(local_size_x = 64) in;
layout(location = 16) uniform uvec4 u_counts;  // instances, lod count, sub-meshes, frame stride
layout(std430, binding = 4) readonly buffer SiRecords { SiInstance si_records[]; };
layout(std430, binding = 5) readonly buffer SiEntries { uint si_entries[]; };
layout(std430, binding = 9) readonly buffer SiBucketInfo { uvec4 si_bucket_info[]; };
void main() {
  uint g = siFlatInvocation();
  uint buckets = u_counts.y * u_counts.z;
  if (g >= si_thread_base[buckets]) return;
  // The last bucket starting at or before g (it is not empty: the next one starts after g).
  uint lo = 0u, hi = buckets;
  while (lo + 1u < hi) {
    uint mid = (lo + hi) / 2u;
    if (si_thread_base[mid] <= g) lo = mid; else hi = mid;
  }
  uvec4 info = si_bucket_info[lo];
  uint local = g - si_thread_base[lo];
  uint i = local / info.x;
  uint k = local - i * info.x;
  uint v = si_entries[si_bucket_offset[lo] + i];
  uint source = si_lod_vertices[info.y + k];
  si_pre_skin_lod = lo / u_counts.z;  // Buckets are LOD-major: lod * sub-meshes + sub-mesh.
  siWritePreSkinned(g, source, si_records[v], siLayer(v), v);
#ifdef SI_MOTION_VECTORS
  si_previous_out[g] =
      vec4(siPreSkinPrevious(source, si_previous_instances[v], siPreviousLayer(v), v), 1.0);
#endif
}
