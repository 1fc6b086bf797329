// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Morph targets (blend shapes: a face's expressions and visemes, a blink, a corrective shape):
/// offsets from the bind pose of the vertices a target moves, scaled by the target's weight and
/// added before skinning, as glTF 2.0 says ("Morph Targets"). A mesh holds them in
/// SkinnedMesh::morph_targets; a clip animates their weights (Clip::morph_tracks); where no
/// clip track covers a target its default_weight holds.
///
/// Usage (the double-precision reference; si::skinVertices applies the weights itself):
/// \code
///   std::vector<double> w(character.mesh.morph_targets.size());
///   si::Status s = si::evaluateMorphWeights(character.mesh, clip, local_time, w);
///   if (s.isOk()) s = si::skinVertices(character.mesh, pose.skinning, positions, normals, {}, w);
/// \endcode

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/span.h"
#include "si/core/status.h"

namespace si {

/// Most morph targets a mesh may have.
inline constexpr size_t kMaxMorphTargets = 256;

/// One morph target, stored sparsely: only the vertices it moves.
struct MorphTarget {
  std::string name;  ///< Optional (glTF's mesh.extras.targetNames).
  /// The vertices it moves (indices into the mesh's vertex arrays), strictly increasing.
  std::vector<uint32_t> vertices;
  /// Offset of each of `vertices` at weight 1, bind-pose model space.
  std::vector<glm::vec3> position_deltas;
  /// Empty, or one per vertex: added to the normal, then the sum renormalized.
  std::vector<glm::vec3> normal_deltas;
  /// Empty, or one per vertex: added to the tangent's xyz, then renormalized (w kept). Only for
  /// a mesh with tangents.
  std::vector<glm::vec3> tangent_deltas;
  /// The weight where no clip track animates the target (glTF's mesh.weights).
  float default_weight = 0.0f;
};

/// Checks targets of a mesh with `vertex_count` vertices (tangents when `has_tangents`); reports
/// the first rule broken, naming the target and entry: at most kMaxMorphTargets
/// (kLimitExceeded); per target, vertices strictly increasing (kNotSorted) and below
/// vertex_count (kOutOfRange); position_deltas one per vertex, normal_deltas and tangent_deltas
/// none or one per vertex, tangent_deltas none without tangents (kCountMismatch); every delta
/// and the default weight finite (kNotFinite).
Status validateMorphTargets(const std::vector<MorphTarget>& targets, size_t vertex_count,
                            bool has_tangents);

/// Each target's default_weight.
std::vector<double> defaultMorphWeights(const std::vector<MorphTarget>& targets);

/// Adds `targets` scaled by `weights` (one per target) to the bind-pose attributes, in double:
/// positions += sum w * delta; normals (and tangents' xyz) likewise, then renormalized (one that
/// cancels to zero length keeps its bind-pose direction). Zero weights are skipped. The spans
/// hold the mesh's attributes on input (normals and tangents may be empty to skip them); the
/// targets must validate against them. kCountMismatch when `weights` does not hold one weight
/// per target.
Status applyMorphTargets(const std::vector<MorphTarget>& targets, Span<const double> weights,
                         Span<glm::dvec3> positions, Span<glm::dvec3> normals,
                         Span<glm::dvec4> tangents);

}  // namespace si
