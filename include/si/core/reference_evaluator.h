// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The double-precision reference evaluation of clips and skinning: the ground truth that every
/// accuracy figure of the library is measured against, and a public API for exact skinned
/// positions (picking, collision, attachments).
///
/// Usage:
/// \code
///   si::ReferencePose pose;
///   si::Status s = si::evaluatePose(character.skeleton, character.clips[0], 0.25, &pose);
///   std::vector<glm::dvec3> positions(character.mesh.vertexCount());
///   std::vector<glm::dvec3> normals(character.mesh.vertexCount());
///   if (s.isOk()) s = si::skinVertices(character.mesh, pose.skinning, positions, normals, {});
/// \endcode

#include <vector>

#include "si/core/baked_palette.h"
#include "si/core/clip.h"
#include "si/core/skeleton.h"
#include "si/core/skinned_mesh.h"
#include "si/core/span.h"
#include "si/core/status.h"
#include "si/core/transform.h"

namespace si {

/// How a time outside [0, duration] is mapped into it.
enum class TimeWrap : uint8_t {
  kDefault = 0,  ///< Use the clip's loop mode.
  kClamp,        ///< Clamp to [0, duration].
  kLoop,         ///< Wrap modulo duration (0 for a zero-length clip).
};

/// Maps `time_seconds` into [0, duration] per `wrap` and the clip's loop mode. A looping clip
/// maps `duration` itself to 0 (except that a zero-length clip maps everything to 0).
double clipLocalTime(const Clip& clip, double time_seconds, TimeWrap wrap = TimeWrap::kDefault);

/// Samples one track at a clip-local time `t` (already mapped by clipLocalTime()). Before the
/// first key the first value holds; after the last key the last value holds, unless `wrap_to`
/// is non-negative: then the span from the last key to `wrap_to + first key time` interpolates
/// towards the first key (see Clip::wrap_interpolates). Rotations are normalized after
/// interpolation and linear interpolation takes the shorter arc. The track must be non-empty
/// and valid (Clip::validate()).
glm::dvec3 sampleTrack(const Vec3Track& track, double t, double wrap_to = -1.0);
glm::dquat sampleTrack(const QuatTrack& track, double t, double wrap_to = -1.0);

/// Joint transforms of one pose in double precision.
struct ReferencePose {
  std::vector<TransformD> local;     ///< Parent space.
  std::vector<glm::dmat4> model;     ///< Model space (root's parent is the identity).
  std::vector<glm::dmat4> skinning;  ///< model * inverse bind: bind-pose vertices to posed.
};

/// Evaluates `clip` at `time_seconds` (mapped with clipLocalTime(clip, time, wrap)) into `pose`,
/// resizing its arrays to the joint count. Joints without a track keep the rest pose.
/// Fails (kInvalidArgument, pose untouched) when `pose` is null, the skeleton or the clip does
/// not validate, or the time is not finite (kNotFinite).
Status evaluatePose(const Skeleton& skeleton, const Clip& clip, double time_seconds,
                    ReferencePose* pose, TimeWrap wrap = TimeWrap::kDefault);

/// Evaluates `clip` at clip-local time `local_time_seconds` in [0, duration] without remapping
/// it: for a looping clip, `duration` itself gives the pose approached from the left (the last
/// key held, or interpolating into the first key when Clip::wrap_interpolates), which is what a
/// baked loop's final frame stores. Times outside [0, duration] are clamped. Fails as
/// evaluatePose() does.
Status evaluateLocalPose(const Skeleton& skeleton, const Clip& clip, double local_time_seconds,
                         ReferencePose* pose);

/// The weight of each of `mesh`'s morph targets in `clip` at clip-local time `local_time_seconds`
/// (mapped and clamped as evaluateLocalPose() does; use clipLocalTime() for a playback time):
/// the clip's morph track where one covers the target (LINEAR, STEP, CUBICSPLINE as glTF says),
/// otherwise the target's default_weight. `out` holds one weight per target. Fails
/// (kCountMismatch, out untouched) for a wrong size, kNotFinite for a time that is not finite,
/// and as Clip::validate(joints, morph target count) for a clip that does not validate.
Status evaluateMorphWeights(const SkinnedMesh& mesh, const Clip& clip, double local_time_seconds,
                            Span<double> out);

/// Fills `pose` with the skeleton's rest pose.
Status evaluateRestPose(const Skeleton& skeleton, ReferencePose* pose);

/// Composes local transforms into model and skinning matrices (joint * inverse bind).
/// `local` must hold one transform per joint; `out_model` and `out_skinning` as many elements
/// (kCountMismatch otherwise). The skeleton is assumed valid.
Status composePose(const Skeleton& skeleton, Span<const TransformD> local,
                   Span<glm::dmat4> out_model, Span<glm::dmat4> out_skinning);
/// The skinning matrices `palette` stores, from one per skeleton joint (composePose's): the
/// palette's joints (BakedPalette::palette_joints, in that order) in float, as
/// CrowdManager::setLivePose takes them. kCountMismatch when `skinning` does not hold one
/// matrix per joint the palette was baked from, or `out` one per palette joint; kOutOfRange
/// for a palette joint past them (a palette that fails its validate()).
Status paletteSkinning(const BakedPalette& palette, Span<const glm::dmat4> skinning,
                       Span<glm::mat4> out);

/// The inverse of composePose(): the local transforms whose composition gives `model` (one
/// model-space joint matrix per joint): each joint's matrix relative to its parent's as
/// composed again from the transforms found, decomposed as T * R * S with R the rotation of its
/// 3x3's polar decomposition and S the scale along R's axes (negative along x for a mirroring
/// matrix). A pose of rotations and scales without shear comes back exactly (to rounding);
/// from blended matrices (rows lerped between frames or crossfaded) what is lost is each
/// joint's own shear, never its origin: every joint's origin composes back where `model` puts
/// it. kCountMismatch for spans of the wrong size; kNotFinite for a matrix that is not finite
/// or whose 3x3 (or its parent's) is singular.
Status decomposePose(const Skeleton& skeleton, Span<const glm::dmat4> model,
                     Span<TransformD> out_local);
/// Skins the mesh's vertices with `skinning` (one matrix per joint), in double, after adding its
/// morph targets (si::applyMorphTargets) at `morph_weights`, one per target (empty: each
/// target's default weight): position = sum w_i * M_i * p; normal = normalize(sum w_i * N_i * n)
/// with N_i the inverse transpose of M_i's upper 3x3 (computed as sign(det) * cofactor, so it stays
/// finite for zero scale; a normal that degenerates to zero length is output as the bind-pose
/// normal); tangent xyz = normalize(sum w_i * M_i3x3 * t), w kept. Zero weights are skipped.
/// `out_positions` must hold vertexCount() elements; `out_normals` and `out_tangents` the same or
/// be empty to skip them (out_tangents requires the mesh to have tangents). Fails with
/// kCountMismatch for wrong sizes, kOutOfRange for a joint index past `skinning`, and as
/// si::validateMorphTargets() for targets that do not validate.
Status skinVertices(const SkinnedMesh& mesh, Span<const glm::dmat4> skinning,
                    Span<glm::dvec3> out_positions, Span<glm::dvec3> out_normals,
                    Span<glm::dvec4> out_tangents, Span<const double> morph_weights = {});

}  // namespace si
