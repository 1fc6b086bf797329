// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Root motion applied to instances (si/core/root_motion.h): an instance that opted in moves by
// its playback's baked motion between the crowd clock it last moved at and now. Playback time
// is a line in unwrapped clip time, so the motion over any span is M(u0)^-1 * M(u1) with one
// cycle per loop boundary crossed: exact for any time step, not stepped.

#include <cstdint>
#include <vector>

#include "crowd/instance_store.h"
#include "crowd/playback.h"
#include "si/core/baked_palette.h"

namespace si::detail {

/// Moves instance `i` (opted in) by its root motion from its motion clock to `clock` and sets
/// its motion clock to `clock`. During a crossfade the two clips' motions over the span are
/// blended by the new clip's weight at the span's middle. A motion that would leave the
/// position or rotation not finite is dropped.
/// `clips` are the palette's clip timings.
void applyRootMotion(const BakedPalette& palette, const std::vector<ClipTiming>& clips,
                     double clock, InstanceStore& st, uint32_t i);

/// The same for every instance of [begin, end) that opted in; each one that moved is stamped
/// with the store's version (InstanceStore::stamp: bump it first).
void applyRootMotion(const BakedPalette& palette, const std::vector<ClipTiming>& clips,
                     double clock, InstanceStore& st, uint32_t begin, uint32_t end);

}  // namespace si::detail
