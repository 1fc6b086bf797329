// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// SI_INSTANCE_HANDLE (a material that reads SiSurface.instance: MaterialDesc::instance_handle):
// the vertex stage's flat output of the drawn instance's InstanceHandle::id, and where each
// path finds it. GPU-driven (SI_GPU_DRIVEN): the cull pass's visible list (its w word).
// drawCrowd's instanced paths: one 32-bit handle per drawn slot (InstanceBatcher::buildHandles)
// at storage binding 29, the slot being the batch's first (u_batch_slot) plus the instance's
// place in the batch. The baselines (SI_INSTANCE_HANDLE_UNIFORM: one draw per instance): a
// uniform. Without SI_INSTANCE_HANDLE, nothing: the surface reads 0.
#ifndef SI_INSTANCE_HANDLE_GLSL
#define SI_INSTANCE_HANDLE_GLSL
#ifdef SI_INSTANCE_HANDLE
SI_VARYING_LAYOUT(11) flat out uint v_instance_handle;
#if defined(SI_INSTANCE_HANDLE_UNIFORM)
uniform uint u_instance_handle;
#elif !defined(SI_GPU_DRIVEN)
#include "batch_slot.glsl"
layout(std430, binding = 29) readonly buffer SiSlotHandles { uint si_slot_handles[]; };
// The handle of the batch's instance `place`.
uint siSlotHandle(uint place) { return si_slot_handles[u_batch_slot + place]; }
#endif
#endif
#endif
