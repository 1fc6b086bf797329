// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling: the bindings shared by its three passes.
#ifndef SI_CULL_COMMON_GLSL
#define SI_CULL_COMMON_GLSL
#include "si_instance_record.glsl"
#include "gpu_crowd_state.glsl"
layout(std430, binding = 0) readonly buffer SiState { SiGpuInstance si_state[]; };
layout(std430, binding = 1) readonly buffer SiClips { SiGpuClip si_clips[]; };
layout(std430, binding = 2) readonly buffer SiTimes { double si_times[]; };
#include "cull_counters.glsl"
layout(std430, binding = 4) writeonly buffer SiRecordsOut { SiInstance si_records[]; };
layout(std430, binding = 5) buffer SiEntriesOut { uint si_entries[]; };
layout(std430, binding = 6) buffer SiVisible { uvec4 si_visible[]; };  // index, lod, mask, handle
layout(location = 16) uniform uvec4 u_counts;  // instances, lod count, sub-meshes, frame stride
// Per bucket: x vertices of its pre-skinning list, y offset of the list, z first local index,
// w local index count (PreSkinLists).
layout(std430, binding = 9) readonly buffer SiBucketInfo { uvec4 si_bucket_info[]; };
#endif
