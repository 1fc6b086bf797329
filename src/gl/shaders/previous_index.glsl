// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// drawCrowd's previous records through an index (after si_skinning.glsl): per drawn slot a
// 32-bit index (InstanceBatcher::buildPreviousIndices), instead of a copy of the previous record
// per slot (buildPrevious). The records are either the previous update's records written once
// each into this frame's ring region (CrowdView::previousRecords(), indexed by number) or the
// previous frame's region, where they still are (indexed by 16-byte word: buildRecordPlaces,
// resources/drawn_regions.h). Slots are numbered as the layer records are
// (DrawBatch::layer_byte_offset / 16 + place in the batch). Storage binding 25 covers both.
#ifndef SI_PREVIOUS_INDEX_GLSL
#define SI_PREVIOUS_INDEX_GLSL
#include "ring_words.glsl"
layout(std430, binding = 25) readonly buffer SiPreviousBlocks { uvec4 si_previous_words[]; };
// In 16-byte words of SiPreviousBlocks: the indices' first word, the records' base word, and
// the words one index step moves (5: an index numbers records; 1: it is a word).
layout(location = 8) uniform uvec3 u_previous;
// Where an instance has no previous record (si::kNoPreviousRecord), its current one
// moved by the cameras' shift (buildPrevious's fallback, the same float addition).
layout(location = 9) uniform vec3 u_previous_shift;

// The previous record of slot `slot`, whose current record is `current`.
SiInstance siPreviousRecord(uint slot, SiInstance current) {
  uint p = si_previous_words[u_previous.x + (slot >> 2u)][slot & 3u];
  if (p == 0xFFFFFFFFu) {
    current.world_rows[0].w += u_previous_shift.x;
    current.world_rows[1].w += u_previous_shift.y;
    current.world_rows[2].w += u_previous_shift.z;
    return current;
  }
  return SI_RECORD_AT(si_previous_words, u_previous.y + u_previous.z * p);
}
#endif
