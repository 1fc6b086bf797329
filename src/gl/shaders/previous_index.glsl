// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// drawCrowd's previous records through an index (after si_skinning.glsl): per drawn slot a
// 32-bit index into the previous update's records, which the renderer writes once each into
// the ring (CrowdView::previousRecords(); the indices: InstanceBatcher::buildPreviousIndices),
// instead of a copy of the previous record per slot (buildPrevious). Slots are numbered as the
// layer records are (DrawBatch::layer_byte_offset / 16 + place in the batch). Both blocks are
// bound at storage binding 25 from the index block's start.
#ifndef SI_PREVIOUS_INDEX_GLSL
#define SI_PREVIOUS_INDEX_GLSL
#include "ring_words.glsl"
layout(std430, binding = 25) readonly buffer SiPreviousBlocks { uvec4 si_previous_words[]; };
// The first word of the previous records in SiPreviousBlocks.
layout(location = 8) uniform uint u_previous_records;
// Where an instance has no previous record (CrowdManager::kNoPreviousRecord), its current one
// moved by the cameras' shift (buildPrevious's fallback, the same float addition).
layout(location = 9) uniform vec3 u_previous_shift;

// The previous record of slot `slot`, whose current record is `current`.
SiInstance siPreviousRecord(uint slot, SiInstance current) {
  uint p = si_previous_words[slot >> 2u][slot & 3u];
  if (p == 0xFFFFFFFFu) {
    current.world_rows[0].w += u_previous_shift.x;
    current.world_rows[1].w += u_previous_shift.y;
    current.world_rows[2].w += u_previous_shift.z;
    return current;
  }
  return SI_RECORD_AT(si_previous_words, u_previous_records + 5u * p);
}
#endif
