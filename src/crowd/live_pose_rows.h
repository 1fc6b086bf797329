// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The engine's joint matrices of a live pose (CrowdManager::setLivePose) checked, stored as
// palette rows (the three rows of each 3x4 skinning matrix, one texel each, in the palette's
// format) and bounded (the box its vertices lie in, from the palette's joint bounds). The poses
// of a thousand instances of 60 joints pass here every frame, so storePose checks, stores and
// bounds them in one pass, with no branch per value: one joint at a time in SSE2's four lanes
// (every x86-64; live_pose_rows_sse2.cpp), two at a time in AVX's eight with F16C's half-float
// conversion where the CPU has them (live_pose_rows_avx.cpp). The Reference versions here do
// the same one value at a time: the tests hold every variant equal to them, and builds without
// SSE2 use them. No GL.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/baked_palette.h"
#include "si/core/bounds.h"
#include "si/core/span.h"

namespace si::detail {

/// The first of `skinning` whose last row is not 0 0 0 1 or which holds a value whose
/// magnitude passes `range` (or is not finite), or skinning.size() when there is none.
size_t firstBadJointReference(Span<const glm::mat4> skinning, float range);

/// Stores each of `skinning`'s first three rows as texels `j * joint_stride_texels + row` of
/// `frame` in `format` (kMatrix3x4F32, or kMatrix3x4F16 rounded to nearest even as
/// floatToHalf does). Every value must pass firstBadJoint's check with the format's range.
void storeJointRowsReference(PaletteFormat format, Span<const glm::mat4> skinning,
                             uint32_t joint_stride_texels, uint8_t* frame);

/// A palette joint's bind-pose box (BakedPalette::joint_bounds) as storePose reads it: its centre
/// and half extents (xyz; w 0). An empty box (nothing drawn follows the joint) has half
/// extents of -1 and adds nothing.
struct JointBox {
  glm::vec4 center{0.0f}, half{-1.0f, -1.0f, -1.0f, 0.0f};
};
std::vector<JointBox> jointBoxes(Span<const Aabb> joint_bounds);

/// The box holding every vertex skinned by `skinning` (model-space matrices, one per palette
/// joint) whose joints' bind-pose boxes `joints` hold it: the union of each joint's box carried
/// by its matrix (centre moved, half extents through the matrix's absolute values), so any
/// convex blend of the joints' transforms of a vertex lies inside. Empty when every joint's box
/// is; not a number when a carried centre is not (matrices so large that their products
/// overflow to infinities of both signs). Unpadded.
Aabb poseBoxReference(Span<const glm::mat4> skinning, Span<const JointBox> joints);

/// How storePose runs: one value at a time (the references), one joint at a time in SSE2's
/// four lanes (every x86-64), or two at a time in AVX's eight with F16C's half-float conversion
/// (x86-64 CPUs since 2012, where the OS keeps AVX state). kBest: the fastest this build and CPU
/// run.
enum class PoseRowsIsa { kReference, kSse2, kF16c, kBest };
/// Whether this build and CPU run `isa` (kReference and kBest always).
bool runs(PoseRowsIsa isa);

/// A live pose checked, stored and bounded in one pass over its matrices: returns
/// firstBadJointReference(skinning, range) (`range`: the format's, 65504 for half floats), and
/// when that is skinning.size() (every matrix good) has stored storeJointRowsReference's texels
/// into `frame` and set *box to poseBoxReference's box (empty for no `joints`), both exactly.
/// Past a bad matrix, what `frame` and *box hold is unspecified. `isa` must run (runs()).
size_t storePose(PaletteFormat format, Span<const glm::mat4> skinning, uint32_t joint_stride_texels,
                 Span<const JointBox> joints, float range, uint8_t* frame, Aabb* box,
                 PoseRowsIsa isa = PoseRowsIsa::kBest);

}  // namespace si::detail
