// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The geometric error of a mesh's LODs, in model units, and what a crowd selects LODs by:
/// LOD k's error is how far its bind-pose surface may lie from LOD 0's, a two-sided Hausdorff
/// distance estimated from both meshes' vertices and triangle centroids. Screen-space-error
/// LOD selection (si::CrowdDesc::lod_mode) projects it to pixels.
///
/// Usage:
/// \code
///   si::Status s = si::measureLodErrors(&character.mesh, false);  // fills what is missing
///   std::vector<float> per_level;
///   s = si::lodErrorsByLevel(character.mesh, &per_level);          // -> CrowdDesc
/// \endcode

#include <vector>

#include <glm/glm.hpp>

#include "si/core/character.h"
#include "si/core/skinned_mesh.h"
#include "si/core/span.h"
#include "si/core/status.h"

namespace si {

/// The largest distance from any of `points` to the surface of `triangles` (a triangle list
/// indexing `positions`), in the positions' units; 0 when there are no points. The triangles
/// must be non-empty and index inside `positions` (kInvalidArgument otherwise).
Status maxDistanceToSurface(Span<const glm::vec3> positions, Span<const uint32_t> triangles,
                            Span<const glm::vec3> points, float* out);

/// The two-sided surface distance between two triangle lists of the same vertex positions:
/// the larger of (a's vertices and centroids to b's surface) and (b's to a's).
Status surfaceDistance(Span<const glm::vec3> positions, Span<const uint32_t> a,
                       Span<const uint32_t> b, float* out);

/// Measures every sub-mesh's LOD errors against its LOD 0 in the bind pose (surfaceDistance)
/// into SubMesh::lod_error_units: only for sub-meshes that have none, or for all when
/// `overwrite`. An empty level (a dropped part, si::buildPartLods) keeps its given error; one
/// without an error fails with kInvalidArgument. Fails, leaving the mesh untouched, with the status of SkinnedMesh::validate()
/// for a mesh that is not valid for its own joints.
Status measureLodErrors(SkinnedMesh* mesh, bool overwrite);

/// Options of measureAnimatedLodErrors().
struct AnimatedLodErrorDesc {
  /// Poses sampled per clip, evenly over its duration (its last frame included); 0 means 8.
  uint32_t poses_per_clip = 0;
  /// Poses measured in all, clips taken in order (a hostile file's thousands of clips must not
  /// run for minutes); 0 means 256.
  uint32_t max_poses = 0;
};

/// Raises every sub-mesh's LOD errors to the largest surface distance from LOD 0 over the
/// rest pose and poses sampled from the character's clips (both meshes skinned alike): a
/// simplification that welds vertices of different joints (legs merged in the bind pose) is
/// small there and large once they move apart. Errors are only raised (never lowered) and kept
/// non-decreasing along each chain; sub-meshes without errors are measured in the bind pose
/// first. Empty levels (dropped parts) keep the error they have. Fails, leaving the character untouched, with kInvalidArgument for a null character
/// and the status of the evaluator or of SkinnedMesh::validate() for an invalid one.
/// `worst_pose_clip` (may be null) receives, per sub-mesh and level, the clip index of the
/// worst pose (-1: the rest pose or bind pose).
Status measureAnimatedLodErrors(Character* character, const AnimatedLodErrorDesc& desc,
                                std::vector<std::vector<int>>* worst_pose_clip = nullptr);

/// One LOD level as an instance draws it (a sub-mesh with fewer levels draws its last).
struct LodLevelSummary {
  uint64_t triangles = 0;  ///< Of all sub-meshes at this level.
  float error_units = 0;   ///< lodErrorsByLevel()'s value.
};

/// The mesh's levels, finest first: triangles and error each (for reports: si-bake, the demo).
/// Fails as lodErrorsByLevel() does.
Status summarizeLodLevels(const SkinnedMesh& mesh, std::vector<LodLevelSummary>* out);

/// The error of each LOD level as an instance draws it: for level l, the largest error of any
/// sub-mesh at l (a sub-mesh with fewer levels draws its last), then made non-decreasing, so a
/// coarser level never claims less error than a finer one. maxLodCount() entries; level 0 is
/// 0. kInvalidArgument when a sub-mesh has no errors (measure them first) or `out` is null.
Status lodErrorsByLevel(const SkinnedMesh& mesh, std::vector<float>* out);

}  // namespace si
