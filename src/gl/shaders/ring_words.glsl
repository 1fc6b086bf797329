// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// drawCrowd's record ring read by 16-byte word (after si_instance_record.glsl), for the passes
// that find their records through a table or an index rather than a bound uniform block:
// SiRing, the frame's region from its start at storage binding 24 (the compose pass), and
// SI_RECORD_AT, a record from any such array of words.
#ifndef SI_RING_WORDS_GLSL
#define SI_RING_WORDS_GLSL
layout(std430, binding = 24) readonly buffer SiRing { uvec4 si_ring[]; };

// The record whose first word is `word` of the uvec4 array `words`.
#define SI_RECORD_AT(words, word)                                                 \
  SiInstance(vec4[3](uintBitsToFloat(words[word]), uintBitsToFloat(words[word + 1u]), \
                     uintBitsToFloat(words[word + 2u])),                          \
             words[word + 3u], words[word + 4u])
SiInstance siRingRecord(uint word) { return SI_RECORD_AT(si_ring, word); }
#endif
