// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the baker measures of a baked clip: its error against the double-precision reference
// (emulating the shader) and its conservative culling box.
#include <cstdint>
#include <vector>

#include "si/bake/animation_baker.h"

namespace si::detail {

/// Emulates the shader at the clip's measurement times and compares with the reference: every
/// frame interval's midpoint and the clip's end on every one of `vertices`; unless
/// `midpoints_only`, also fractions 0, 1/4 and 3/4 of each interval, on `short_list` when given
/// (else on `vertices`). `mesh` is the character's mesh or a subset of its vertices,
/// `gpu_mesh` the same with the weights the vertex format stores; `vertices` and `short_list`
/// index into both. The reference skins `mesh`, the emulation `gpu_mesh`, so the error
/// includes the vertex format's quantization; the two are subtracted per joint before the
/// vertex is transformed, so float keeps the small difference's precision.
/// `interval_errors`, when not null, receives the largest error measured in each frame
/// interval (frame_count - 1 entries; the clip's end counts in the last). Memory stays within
/// a frame's joints plus 1 % of the samples (the P99 is exact).
Status measureClip(const Character& character, const SkinnedMesh& mesh,
                   const SkinnedMesh& gpu_mesh, const BakedPalette& p, uint32_t clip_index,
                   const std::vector<uint32_t>& vertices, double shell_distance,
                   bool midpoints_only, ClipErrorReport* out,
                   std::vector<double>* interval_errors = nullptr,
                   const std::vector<uint32_t>* short_list = nullptr);

/// Box of everything the shader can draw of clip `clip_index`: `vertices` of `gpu_mesh` at
/// every frame for a linear clip (matrix lerps stay on chords); for a cubic clip, per interval
/// the box of the frames it reads widened by 1/8 of its extent per axis (the most the
/// Catmull-Rom weights, extrapolated ends included, leave it). Not padded for rounding or the
/// rotation format's normalization; the caller pads.
Status clipBounds(const BakedPalette& p, uint32_t clip_index, const SkinnedMesh& gpu_mesh,
                  const std::vector<uint32_t>& vertices, Aabb* out);

/// For the automatic rate search: per stored joint, the 8 drawn vertices of `mesh` weighted to
/// it that lie farthest from its bind position, and per morph target the 8 drawn vertices it
/// moves farthest (indices into `mesh`, sorted, once each). Chosen
/// once, on the reference mesh: the stored mesh (quantized weights, where a tiny weight may read
/// 0) is measured at the same vertices.
std::vector<uint32_t> searchVertices(const Character& character, const SkinnedMesh& mesh,
                                     const std::vector<uint32_t>& drawn);
/// The `vertices` of `mesh` as a mesh of their own (positions, normals, joints, weights,
/// joints1, weights1, and the morph targets' entries of those vertices, renumbered).
SkinnedMesh subsetMesh(const SkinnedMesh& mesh, const std::vector<uint32_t>& vertices);
/// `mesh` with the weights the vertex format stores (si::quantizeWeights, both sets together):
/// what the shaders skin with.
SkinnedMesh storedWeightsMesh(const SkinnedMesh& mesh);

}  // namespace si::detail
