// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Hostile glTF seeds for the glTF fuzzers and their replays (si_write_fuzz_seeds gltf): a small
// skinned, animated file that imports, and some 60 variants of it, each breaking one rule
// (cycles and two parents in the node graph, joints past the skin or the nodes, accessors past
// their views and buffers, counts past 32 bits, odd strides, NaN, infinite and past-float
// values in weights, positions, bind matrices, key times and rotations, decreasing times,
// cubic keys without tangents, unknown paths and interpolations, morph targets and sparse
// accessors that name nothing, a skeleton under 4000 nodes). The importer must refuse each by
// name or give a character that validates, and the bake must survive what imports.

#include <string>

namespace si::fuzz {

/// Writes the files into `dir` (which must exist); 0, or 1 after naming what failed.
int writeHostileGltfs(const std::string& dir);

}  // namespace si::fuzz
