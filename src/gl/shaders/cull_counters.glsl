// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling's counters (std430, binding 3): what the cull pass counts, the command pass
// turns into prefix sums, dispatch sizes and the pre-skinning split, and the later passes read.
// Renderer code clears only the visible count and the bucket counts each frame.
#ifndef SI_CULL_COUNTERS_GLSL
#define SI_CULL_COUNTERS_GLSL
layout(std430, binding = 3) coherent buffer SiCounters {
  uint si_visible_count; uint si_pad0, si_pad1, si_pad2;
  uint si_bucket_count[256];   // Instances per (LOD, sub-mesh) bucket.
  uint si_cursor[256];         // The scatter pass's next entry per bucket.
  uint si_dispatch[4];         // The scatter pass's groups.
  uint si_skin_dispatch[4];    // The pre-skinning pass's groups (x, y, z) and threads (w).
  uint si_bucket_offset[256];  // First entry of each bucket.
  uint si_thread_base[257];    // First pre-skinning thread (ring vertex) of each bucket; the
                               // entry after the last bucket is the total.
  uint si_fitted[256];         // Instances of each bucket pre-skinned; the rest are drawn with
                               // vertex-shader skinning (the ring is full, or no pre-skinning).
  uint si_impostor_dispatch[4];  // The impostor quads pass's groups (x, y, z) and quads (w).
  uint si_impostors_drawn;       // The quads it kept (the others hold no pixel centre).
};
#endif
