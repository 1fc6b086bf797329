// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The staged upload's scatter (src/gl/resources/upload_ring.h): one thread per 32-bit word of
// the pieces staged in the ring, copying it to its place in the target buffer. The staged region
// starts with a table of the pieces, one uvec4 each (x: the piece's first staged word, y: its
// first word in the target, z: its words, w: its first thread, increasing), then their words.
#include "dispatch_index.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer SiStaged { uint si_staged[]; };
layout(std430, binding = 1) writeonly buffer SiTarget { uint si_target[]; };
layout(location = 0) uniform uint u_pieces;
layout(location = 1) uniform uint u_words;  // Words of all pieces: the threads that copy.

void main() {
  uint g = siFlatInvocation();
  if (g >= u_words) return;
  // The last piece whose first thread is at or before g.
  uint lo = 0u, hi = u_pieces;
  while (lo + 1u < hi) {
    uint mid = (lo + hi) / 2u;
    if (si_staged[4u * mid + 3u] <= g) lo = mid; else hi = mid;
  }
  uint k = g - si_staged[4u * lo + 3u];
  si_target[si_staged[4u * lo + 1u] + k] = si_staged[si_staged[4u * lo] + k];
}
