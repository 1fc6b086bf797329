// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// drawCrowd: the batch's first slot, numbered as the layer records are (its layer records'
// first index in the layer block, DrawBatch::layer_byte_offset / 16): where its composed
// records, previous indices and instance handles start. GPU-driven draws leave it 0.
#ifndef SI_BATCH_SLOT_GLSL
#define SI_BATCH_SLOT_GLSL
layout(location = 7) uniform uint u_batch_slot;
#endif
