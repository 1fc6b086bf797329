// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// A skinned triangle mesh with switchable sub-meshes (the technique's armour pieces and weapons)
/// and several levels of detail per sub-mesh, plus helpers to clean up skin weights.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/gtc/type_precision.hpp>

#include "si/core/morph_target.h"
#include "si/core/span.h"
#include "si/core/status.h"

namespace si {

/// Largest |sum of weights - 1| that validate() accepts for a vertex.
inline constexpr float kWeightSumTolerance = 1e-3f;
/// Influences in one set (SkinnedMesh::joints/weights, and joints1/weights1): what
/// reduceInfluences() keeps.
inline constexpr size_t kMaxInfluences = 4;
/// Most influences a vertex may have: both sets.
inline constexpr size_t kMaxVertexInfluences = 8;

/// One (joint, weight) influence on a vertex.
struct Influence {
  uint32_t joint = 0;
  float weight = 0.0f;
};

/// A range of `SkinnedMesh::indices`: `index_count` indices (a multiple of 3) from `first_index`.
struct IndexRange {
  uint32_t first_index = 0;
  uint32_t index_count = 0;
};

/// A named group of triangles that can be switched on or off per instance. `lods[0]` is the most
/// detailed level; later entries are coarser versions of the same piece, or empty (index_count
/// 0): the piece is not drawn at that level (si::buildPartLods drops parts that lie within the
/// level's error of the rest).
struct SubMesh {
  std::string name;
  std::vector<IndexRange> lods;
  uint32_t material = 0;  ///< Index into the owning Character's materials.
  /// Geometric error of each LOD in model units (bind pose): how far its surface may lie from
  /// LOD 0's. One entry per LOD (0 for LOD 0), or empty when unknown. Filled by the LOD chain
  /// builder (si::buildLodChain: the simplifier's own error) or measured (si::measureLodErrors).
  /// Screen-space-error LOD selection (si::CrowdDesc) projects it to pixels.
  std::vector<float> lod_error_units;
};

/// Vertices shared by all sub-meshes and LODs, plus the index ranges that select them.
/// Per-vertex arrays: `positions` defines the vertex count; `normals`, `joints` and `weights`
/// must match it; `tangents`, `texcoords`, `texcoords1`, `colors`, `joints1`, `weights1` and
/// `vertex_materials` are empty or match it.
///
/// Parts and variations: a sub-mesh is what an instance can switch (its bit in the variation
/// mask); what it draws may be many parts with different materials, merged into its index
/// ranges, each vertex naming its material in `vertex_materials`. One draw then covers every
/// material of a sub-mesh.
struct SkinnedMesh {
  /// Most sub-meshes a mesh may have (an instance's variation mask has 32 bits).
  static constexpr size_t kMaxSubMeshes = 32;

  std::vector<glm::vec3> positions;    ///< Bind-pose model space.
  std::vector<glm::vec3> normals;      ///< Unit length.
  std::vector<glm::vec4> tangents;     ///< Optional; xyz unit, w = +-1 (bitangent sign).
  std::vector<glm::vec2> texcoords;    ///< Optional.
  /// Optional: a second set of texture coordinates (glTF TEXCOORD_1), which the shaders hand a
  /// material as SiSurface.uv1 (the built-in material does not read it).
  std::vector<glm::vec2> texcoords1;
  /// Optional: each vertex's colour (glTF COLOR_0), linear RGBA, each channel in [0, 1]. It
  /// multiplies the material's base colour, as glTF says; the GPU keeps 8 bits a channel.
  std::vector<glm::vec4> colors;
  std::vector<glm::u16vec4> joints;    ///< Up to 4 joint indices per vertex.
  std::vector<glm::vec4> weights;      ///< Matching weights, >= 0, summing to 1.
  /// Optional: influences 5 to 8 of each vertex (glTF JOINTS_1/WEIGHTS_1), for a character
  /// whose vertices 4 influences do not place closely enough (GltfImportReport's fold error).
  /// With them, `weights` and `weights1` together sum to 1, and every path skins all 8 (an
  /// 8-influence vertex stream: a little dearer to skin).
  std::vector<glm::u16vec4> joints1;
  std::vector<glm::vec4> weights1;
  /// Optional: each vertex's material (index into the owning Character's materials). Empty:
  /// every vertex takes its sub-mesh's `material` (resolvedVertexMaterials()).
  std::vector<uint16_t> vertex_materials;
  std::vector<uint32_t> indices;       ///< Triangle list.
  std::vector<SubMesh> sub_meshes;
  /// Optional: blend shapes added to the bind pose before skinning, each weighted by the clip
  /// (Clip::morph_tracks) or its default weight (si/core/morph_target.h).
  std::vector<MorphTarget> morph_targets;

  size_t vertexCount() const { return positions.size(); }
  /// Influences each vertex has: 8 with joints1/weights1, else 4.
  size_t influenceCount() const { return joints1.empty() ? kMaxInfluences : kMaxVertexInfluences; }
  /// Influence k (below influenceCount()) of vertex v: k < 4 from joints/weights, else from
  /// joints1/weights1.
  Influence influence(size_t v, size_t k) const {
    return k < kMaxInfluences ? Influence{joints[v][int(k)], weights[v][int(k)]}
                              : Influence{joints1[v][int(k - 4)], weights1[v][int(k - 4)]};
  }
  /// The largest number of LOD levels of any sub-mesh.
  size_t maxLodCount() const;
  /// Triangles drawn for `sub_mesh` at `lod` (the last LOD if `lod` is past it), 0 if invalid.
  size_t triangleCount(size_t sub_mesh, size_t lod) const;

  /// Checks against a skeleton of `joint_count` joints; reports the first rule broken, naming
  /// the array and element:
  /// - at least one vertex (kInvalidArgument); normals, joints, weights match the vertex count
  ///   and tangents, texcoords, texcoords1, colors, joints1, weights1, vertex_materials are
  ///   empty or match it, joints1 and weights1 both (kCountMismatch);
  /// - every attribute finite (kNotFinite); weights not negative, colours in [0, 1]
  ///   (kOutOfRange); each vertex's
  ///   weights (both sets) sum to 1 within kWeightSumTolerance (kInvalidArgument; see
  ///   normalizeWeights());
  /// - joint indices below `joint_count` (kOutOfRange);
  /// - indices: count a multiple of 3 (kInvalidArgument), each below the vertex count
  ///   (kOutOfRange);
  /// - 1 to kMaxSubMeshes sub-meshes (kLimitExceeded), each with at least one LOD, LOD 0
  ///   non-empty, every range triangle aligned and inside `indices` (kOutOfRange); a level past
  ///   LOD 0 may be empty: the sub-mesh is not drawn at that level (si::buildPartLods);
  /// - lod_error_units empty or one per LOD (kCountMismatch), each finite and >= 0
  ///   (kOutOfRange);
  /// - morph_targets as si::validateMorphTargets() says.
  Status validate(size_t joint_count) const;
};

/// The material of every vertex: `mesh.vertex_materials` when it is set, otherwise the
/// `material` of the first sub-mesh whose LOD ranges use the vertex (0 for unused vertices).
std::vector<uint16_t> resolvedVertexMaterials(const SkinnedMesh& mesh);

/// What normalizeWeights() changed.
struct WeightNormalizationReport {
  size_t vertices_changed = 0;   ///< Vertices whose weights were rescaled.
  float max_correction = 0.0f;   ///< Largest |1 - original sum|.
  size_t max_correction_vertex = 0;
};

/// Rescales each vertex's weights (both sets) to sum to 1 and reports the correction. Fails with
/// kInvalidArgument naming the vertex, leaving `mesh` untouched, when a vertex has weights that
/// are negative, not finite, or sum to (nearly) zero: such a vertex has no meaningful binding.
Status normalizeWeights(SkinnedMesh& mesh, WeightNormalizationReport* report);

/// Weights as the GPU vertex format stores them: unsigned normalized 16-bit values that sum to
/// exactly 65535 (rounded, then the largest absorbs the difference), so the shader's blend of
/// matrices stays affine. The weights must be valid (validate()).
glm::u16vec4 quantizeWeights(const glm::vec4& weights);
/// Both sets of an 8-influence vertex quantized together: the 8 sum to exactly 65535.
void quantizeWeights(const glm::vec4& weights, const glm::vec4& weights1, glm::u16vec4* out,
                     glm::u16vec4* out1);
/// The float weights the shader reads back from quantizeWeights().
glm::vec4 dequantizeWeights(const glm::u16vec4& quantized);

/// Keeps the kMaxInfluences largest of `influences` (ties: lower joint index first), renormalized
/// to sum to 1, writing them to `out_joints`/`out_weights` (unused slots: joint 0, weight 0).
/// `*dropped_weight` receives the share of the original total that was dropped (0 to 1).
/// Fails with kInvalidArgument for negative or non-finite weights or a total of zero.
Status reduceInfluences(Span<const Influence> influences, glm::u16vec4* out_joints,
                        glm::vec4* out_weights, float* dropped_weight);

}  // namespace si
