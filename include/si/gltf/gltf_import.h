// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::gltf: glTF 2.0 (.gltf with external or data-URI buffers, .glb) to a si::Character.
/// tinygltf parses the file (a private dependency); every accessor and buffer view is
/// range-checked here, with overflow-safe arithmetic, before a byte is read. docs/gltf.md lists
/// what is supported, what is skipped with a warning and what is an error.
///
/// Usage:
/// \code
///   si::Character fox;
///   si::GltfImportReport report;
///   si::Status s = si::importGltfFile("Fox/glTF-Binary/Fox.glb", {}, &fox, &report);
///   for (const std::string& w : report.warnings) std::puts(w.c_str());
/// \endcode

#include <cstdint>
#include <string>
#include <vector>

#include "si/core/character.h"
#include "si/core/span.h"

namespace si {

/// How skinned primitives become variation groups: the sub-meshes an instance switches with its
/// variation mask (at most 32). Every primitive is a part that is drawn; the parts of a group
/// merge into its index ranges (one draw for all their materials, si::SkinnedMesh).
enum class VariationSource : uint8_t {
  /// A mesh (or its node) named "VAR_<group>" (any case, "_LOD<n>" suffix allowed) belongs to
  /// group <group>; every other primitive is always worn, in group "base" (sub-mesh 0).
  kConvention = 0,
  /// Every glTF mesh is a group named after it (the primitives of a mesh merge).
  kEachMesh,
};

/// An explicit variation group: the meshes (mesh or node names, without "_LOD<n>") it holds.
struct VariationGroupDesc {
  std::string name;
  std::vector<std::string> meshes;
};

/// Import options.
struct GltfImportDesc {
  /// The skin to import: its index, or -1 to pick by `skin_name`, or the only skin.
  int32_t skin_index = -1;
  std::string skin_name;  ///< Used when skin_index is -1 and the file has several skins.
  /// Decode images (every texture of the metallic-roughness materials). When false, or when an
  /// image cannot be decoded, materials keep their factors and no image (a warning says why).
  bool load_images = true;
  /// Loop mode given to every clip (glTF does not say); kDefault means kLoop.
  LoopMode loop_mode = LoopMode::kDefault;
  /// When the asset has no LODs, generate this many coarser levels (si::buildLodChain, at most
  /// 7: each with `lod_index_ratio` of the previous one's triangles, fewer when a sub-mesh
  /// cannot be simplified further); 0 generates none. Every LOD, from the file or generated,
  /// gets its geometric error (SubMesh::lod_error_units).
  uint32_t generate_lods = 0;
  float lod_index_ratio = 0.0f;  ///< 0 means 0.25.
  /// When the file has no animation (or none that touches the skeleton), add one clip named
  /// "rest_pose" holding the skeleton's rest pose (si::makeRestPoseClip), so the character can
  /// be baked and drawn posed; a warning says so. When false, such a character has no clips.
  bool rest_pose_clip_when_none = true;
  /// Where variation groups come from for meshes `variation_groups` does not name.
  VariationSource variations = VariationSource::kConvention;
  /// Explicit groups; they win over `variations` for the meshes they name. A name no skinned
  /// primitive has is kNotFound; an empty or repeated group name kInvalidArgument.
  std::vector<VariationGroupDesc> variation_groups;
  /// Vertices with more than 4 influences (JOINTS_1/WEIGHTS_1) keep their 4 largest, unless
  /// that would move one by more than this fraction of the character's height
  /// (GltfImportReport::max_fold_error_height): then the character keeps all 8
  /// (SkinnedMesh::joints1/weights1: an 8-influence stream, a little dearer to skin). 0 keeps
  /// them wherever a vertex has more than 4; infinity always folds. The default is the bake's
  /// default tolerance.
  float fold_tolerance_height = 1e-4f;
  /// Keep the meshes' morph targets (SkinnedMesh::morph_targets; each node's mesh its own) and
  /// the weights channels that animate them (Clip::morph_tracks); the bake stores their weights
  /// per frame and the draw paths add them before skinning. False drops them, a warning per
  /// mesh (GltfImportReport::dropped_morph_targets): a crowd seen from afar needs no faces.
  bool keep_morph_targets = true;
};

/// What the import did besides the result.
struct GltfImportReport {
  std::vector<std::string> warnings;    ///< One per skipped element, naming it.
  uint32_t skin_joints = 0;             ///< Joints of the chosen skin (the skeleton also holds
                                        ///< their ancestors, so it may have more).
  uint32_t skinned_primitives = 0;
  /// Primitives of nodes no skin moves (a file animated by its nodes, or a mesh a joint
  /// holds): each bound wholly to its node's joint, placed where the node rests.
  uint32_t rigid_primitives = 0;
  uint32_t vertices_renormalized = 0;   ///< Vertices whose weights did not sum to 1.
  float max_weight_correction = 0.0f;
  float max_dropped_weight = 0.0f;      ///< From JOINTS_1/WEIGHTS_1 beyond the 4 largest.
  /// A vertex with more than 4 influences (JOINTS_1/WEIGHTS_1) keeps its 4 largest,
  /// renormalized. What that costs it: the largest distance between where its 4 influences and
  /// where all of them put it (both in double precision), over the rest pose and every clip
  /// sampled at fold_sample_hz and at its end.
  struct FoldedVertex {
    uint32_t vertex = 0;          ///< Index in Character::mesh.
    float dropped_weight = 0.0f;  ///< The share of its weight the fold dropped.
    double error_units = 0.0;     ///< Model units.
  };
  std::vector<FoldedVertex> folded_vertices;  ///< In vertex order; empty without JOINTS_1.
  double max_fold_error_units = 0.0;          ///< The largest of folded_vertices' errors,
  double max_fold_error_height = 0.0;         ///< and as a fraction of Character::height().
  /// 30, or evenly less where the clips would take more than 4096 poses or the folded vertices
  /// times the poses would pass 2e7 (the import's time stays bounded); 0 without folds.
  double fold_sample_hz = 0.0;
  /// The fold was past GltfImportDesc::fold_tolerance_height: the character kept all 8
  /// influences (folded_vertices then says what folding would have cost).
  bool kept_eight_influences = false;
  uint32_t generated_lods = 0;
  /// Morph targets kept (GltfImportDesc::keep_morph_targets) and their entries (a vertex a
  /// target moves), or dropped.
  uint32_t morph_targets = 0;
  uint64_t morph_target_entries = 0;
  uint32_t dropped_morph_targets = 0;
  bool added_rest_pose_clip = false;    ///< See GltfImportDesc::rest_pose_clip_when_none.
  uint32_t parts = 0;                   ///< Distinct parts (a primitive with its LOD levels).
  /// Per variation group (sub-mesh, in order): its name, parts, materials and how it was formed.
  struct Group {
    std::string name;
    uint32_t parts = 0, materials = 0;
    std::string source;  ///< "convention", "each mesh", "option" or "always worn".
  };
  std::vector<Group> groups;
  uint32_t materials = 0;               ///< Character materials (index 0: the default white).
  uint32_t images = 0;                  ///< Decoded images (every texture the materials use).
  /// Vertices whose tangents were generated (si::generateTangents): a material has a normal
  /// map and the file has no TANGENT for every primitive; 0 otherwise.
  uint32_t generated_tangents = 0;
  uint32_t degenerate_tangents = 0;     ///< Of those, vertices without a usable UV gradient.
};

/// Imports a .gltf or .glb file. External URIs resolve against the file's folder and may not
/// leave it; no path expansion happens. Fails (with `out` untouched) with kIo for a file that
/// cannot be read, kCorrupt naming the accessor, buffer view, animation or node for malformed
/// or out-of-range data, kNotFound/kAmbiguous for the skin choice, kUnsupported for an asset
/// without a triangle mesh, and the codes of Character::validate().
///
/// A mesh moved by its node rather than a skin (a file animated by its nodes: machines, props,
/// birds; or a mesh a skinned file hangs on a joint) is a rigid part: its node, and every
/// ancestor, are joints of the skeleton, the node's channels its clips' tracks, and each vertex
/// is bound wholly to the node's joint where the node rests. Every path then draws it.
Status importGltfFile(const std::string& path, const GltfImportDesc& desc, Character* out,
                      GltfImportReport* report);

/// Imports from memory: a .glb (magic "glTF") or .gltf JSON. `base_dir` resolves external URIs
/// (empty: external URIs are refused). Fails like importGltfFile().
Status importGltfMemory(Span<const uint8_t> bytes, const std::string& base_dir,
                        const GltfImportDesc& desc, Character* out, GltfImportReport* report);

}  // namespace si
