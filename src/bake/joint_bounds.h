// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Each palette joint's box in the bind pose (BakedPalette::joint_bounds), what bounds a pose
// the engine gives for culling (docs/crowd.md, "Live poses").
#include <cstdint>
#include <vector>

#include "si/core/baked_palette.h"
#include "si/core/skinned_mesh.h"

namespace si::detail {

/// Per palette joint of `p`, the box of `vertices` of `gpu_mesh` weighted to it (a weight other
/// than 0), each vertex widened per axis by the sum over the morph targets moving it of its
/// delta's magnitude on that axis times the largest magnitude the palette's frames give the
/// target's weight, then padded by 1e-5 of the box's size for rounding; an empty box for a
/// joint none of `vertices` is weighted to (nothing drawn follows it).
std::vector<Aabb> jointBounds(const BakedPalette& p, const SkinnedMesh& gpu_mesh,
                              const std::vector<uint32_t>& vertices);

}  // namespace si::detail
