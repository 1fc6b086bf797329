// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// glTF 2.0 import, internal: the pieces convert() is made of (Khronos glTF 2.0 specification,
// "Skins", "Meshes", "Materials", "Animations", "Accessors"), one file each. tinygltf parses;
// every read checks its range first, in 64-bit arithmetic.

#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <vector>

#include "core/str_cat.h"
#include "si/gltf/gltf_import.h"

namespace si::detail {

inline Status corrupt(const std::string& what) { return {StatusCode::kCorrupt, "glTF: " + what}; }

// ---- gltf_io.cpp: tinygltf's file and image callbacks.
/// Files are read only inside `base_dir` (no path expansion, no escape); an empty base_dir
/// reads nothing. Writing is refused.
struct FsContext {
  std::string base_dir;
};
/// Images are decoded when `load`; one that cannot be decoded is a warning, not an error.
struct ImageContext {
  bool load;
  std::vector<std::string>* warnings;
};
void installCallbacks(tinygltf::TinyGLTF* loader, FsContext* fs, ImageContext* images);
/// Parses a .glb (magic "glTF") or .gltf JSON in memory into `model` with those callbacks
/// (kLimitExceeded past 2 GiB, kCorrupt when tinygltf cannot parse it); its warnings are added.
Status parseGltf(Span<const uint8_t> bytes, const std::string& base_dir, bool load_images,
                 std::vector<std::string>* warnings, tinygltf::Model* model);
/// Resets `report` (a local one where null), parses `bytes` (parseGltf, its warnings into the
/// report) and hands the model to `convert(model, report)`.
template <class Convert>
Status parseAndConvert(Span<const uint8_t> bytes, const std::string& base_dir, bool load_images,
                       GltfImportReport* report, Convert&& convert) {
  GltfImportReport local;
  GltfImportReport& r = report ? *report : local;
  r = GltfImportReport();
  tinygltf::Model model;
  const Status s = parseGltf(bytes, base_dir, load_images, &r.warnings, &model);
  return s.isOk() ? convert(model, &r) : s;
}
/// Reads the file at `path` whole (kIo when it cannot, or past 2 GiB) and gives its folder.
struct GltfFile {
  std::vector<uint8_t> bytes;
  std::string dir;  // Where its relative URIs point: the file's folder.
};
Status readGltfFile(const std::string& path, GltfFile* out);

// ---- gltf_accessors.cpp: typed, range-checked accessor reads.
extern const std::vector<int> kFloat;              ///< FLOAT components.
extern const std::vector<int> kAnyInt;             ///< Unsigned byte, short or int components.
extern const std::vector<int> kFloatOrNormalized;  ///< FLOAT or normalized integers.
/// Reads accessor `index` into `out` (count x components doubles), checking its type, every
/// range and that each value is finite; sparse accessors are applied. kCorrupt naming `what`.
Status readAccessor(const tinygltf::Model& m, int index, const std::vector<int>& types,
                    const std::vector<int>& component_types, const std::string& what,
                    std::vector<double>* out, int* components_out = nullptr);

// ---- gltf_skeleton.cpp: the chosen skin's skeleton.
struct SkinBinding {
  int skin_index = -1;
  const tinygltf::Skin* skin = nullptr;
  std::vector<int32_t> node_to_joint;  ///< Per node: its joint, or -1 outside the skeleton.
};
/// Chooses the skin (GltfImportDesc), builds the skeleton from its joints and all their
/// ancestors (parents first) with rest poses and inverse bind matrices.
Status convertSkeleton(const tinygltf::Model& m, const GltfImportDesc& desc,
                       GltfImportReport* report, Character* c, SkinBinding* out);

// ---- gltf_mesh.cpp: triangle primitives of nodes skinned by the skin, into the vertex arrays.
/// A triangle primitive's surface: what a skinned part and a prop (gltf_prop.cpp) both read.
struct PrimitiveSurface {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;    ///< From the file, or smooth (area weighted) when it has none.
  std::vector<glm::vec4> tangents;   ///< Empty when the file has none.
  std::vector<glm::vec2> texcoords;  ///< TEXCOORD_0, zeros when the file has none.
  std::vector<glm::vec2> texcoords1;  ///< TEXCOORD_1, zeros when the file has none.
  std::vector<glm::vec4> colors;      ///< COLOR_0 (alpha 1 for RGB), white when the file has none.
  std::vector<uint32_t> indices;     ///< Local, each below the vertex count, a multiple of 3.
  bool has_texcoords = false;
  bool has_texcoords1 = false;
  bool has_colors = false;
  size_t clamped_colors = 0;  ///< COLOR_0 values outside [0, 1], clamped.
  bool generated_normals = false;
};
/// Reads POSITION, NORMAL, TANGENT, TEXCOORD_0, TEXCOORD_1, COLOR_0 and the indices (or 0, 1,
/// ... without), checking counts and ranges (kCorrupt naming `where`). A primitive without
/// vertices reads as empty.
Status readPrimitiveSurface(const tinygltf::Model& m, const tinygltf::Primitive& prim,
                            const std::string& where, PrimitiveSurface* out);

// ---- gltf_nodes.cpp: node matrices and surfaces placed by them.
/// The node's local matrix: its matrix, or T * R * S (the rotation normalized).
glm::dmat4 nodeMatrix(const tinygltf::Node& n);
/// Moves `s` by `m`: positions, normals by its inverse transpose and tangents by its linear
/// part (renormalized; zero ones become +Y and +X), and a mirroring `m` (negative determinant)
/// winds the triangles back and flips the tangents' bitangent sign, so fronts stay outside.
void placeSurface(const glm::dmat4& m, PrimitiveSurface* s);

struct ImportedPrimitive {
  std::string mesh_name;  ///< Mesh name (node name or "mesh<n>" without one), "_LOD<n>" removed.
  std::string node_name;
  uint32_t primitive = 0;  ///< Index in its mesh.
  uint32_t lod = 0;        ///< From the mesh name's "_LOD<n>" suffix.
  uint32_t material = 0;   ///< Character material (0: the default).
  bool rigid = false;      ///< Moved by its node, not a skin (each node's use a part).
  std::vector<uint32_t> indices;  ///< Into the character's vertex arrays.
};
/// A vertex with more influences than a vertex holds (JOINTS_1/WEIGHTS_1): all of them, the
/// joints the skeleton's and the weights summing to 1, before the fold to the largest 4.
struct WideVertex {
  uint32_t vertex = 0;  // In c->mesh.
  uint32_t count = 0;
  float dropped_weight = 0.0f;  // reduceInfluences'.
  Influence influences[8];
};
/// The character's morph targets of each node: its mesh's `count` targets from `first`.
struct NodeMorphTargets {
  uint32_t first = 0;
  uint32_t count = 0;
};
/// Appends every skinned triangle primitive's vertices to c->mesh and fills `out`; the vertices
/// whose fold to 4 influences dropped some weight into `wide`. With `keep_morph_targets`, each
/// node's mesh targets join c->mesh.morph_targets (`node_targets`, one per node, says where);
/// without, they are counted and dropped with a warning per mesh.
Status convertMeshes(const tinygltf::Model& m, const SkinBinding& skin, bool keep_morph_targets,
                     GltfImportReport* report, Character* c, std::vector<ImportedPrimitive>* out,
                     std::vector<WideVertex>* wide, std::vector<NodeMorphTargets>* node_targets);

// ---- gltf_morph_targets.cpp: the meshes' morph targets, sparse.
/// One primitive's deltas of one target, one per vertex of the primitive (empty: the target has
/// no such attribute).
struct PrimitiveMorphDeltas {
  std::vector<glm::vec3> positions, normals, tangents;
};
/// Adds the targets of node `node`'s mesh to c->mesh.morph_targets (names from the mesh's
/// extras.targetNames, else "<where> target <k>"; default weights from the node's weights, else
/// the mesh's, else 0) and says where in `out`. kCorrupt naming `where` for primitives with
/// different target counts or a weight count that is not the target count; kLimitExceeded past
/// kMaxMorphTargets.
Status beginNodeMorphTargets(const tinygltf::Model& m, size_t node, const std::string& where,
                             Character* c, NodeMorphTargets* out);
/// Reads `prim`'s targets (POSITION, NORMAL, TANGENT; each VEC3, float or normalized), each
/// accessor holding `vertex_count` elements (kCorrupt otherwise).
Status readPrimitiveMorphDeltas(const tinygltf::Model& m, const tinygltf::Primitive& prim,
                                const std::string& where, size_t vertex_count,
                                std::vector<PrimitiveMorphDeltas>* out);
/// Moves a rigid part's deltas by `rest` as placeSurface() moves its surface (`unplaced`: the
/// surface before), so the morphed, renormalized normals and tangents stay exact.
void placeMorphDeltas(const glm::dmat4& rest, const PrimitiveSurface& unplaced,
                      std::vector<PrimitiveMorphDeltas>* deltas);
/// Appends the entries that move something (vertices from `first_vertex`) to the node's targets.
void appendMorphDeltas(const std::vector<PrimitiveMorphDeltas>& deltas, uint32_t first_vertex,
                       const NodeMorphTargets& range, Character* c);
/// After the meshes: drops normal or tangent deltas that are all zero, and tangent deltas of a
/// mesh without tangents (a warning each); counts targets and entries into the report.
void finishMorphTargets(GltfImportReport* report, Character* c);

// ---- gltf_influence_fold.cpp: what folding a vertex's influences to 4 costs.
/// Measures, for each of `wide`, how far its 4 influences (c.mesh) put it from where all of
/// them do (both in double), the largest over the rest pose and every clip sampled at
/// kFoldSampleHz and at its end (all clips evenly slower past kFoldMaxPoses poses or
/// kFoldMaxVertexPoses vertices times poses: report->fold_sample_hz), into
/// report->folded_vertices and the largest into report->max_fold_error_units and
/// max_fold_error_height, with a warning naming them. c's skeleton and clips must validate
/// (kCorrupt otherwise).
inline constexpr double kFoldSampleHz = 30.0;
inline constexpr double kFoldMaxPoses = 4096.0;
inline constexpr double kFoldMaxVertexPoses = 2e7;
Status measureInfluenceFold(const Character& c, const std::vector<WideVertex>& wide,
                            GltfImportReport* report);
/// When report->max_fold_error_height passes `tolerance`: each of `wide` takes all its
/// influences, the largest 4 in c->mesh.joints/weights and the rest in joints1/weights1 (every
/// other vertex none there), and report->kept_eight_influences says so.
void keepWideInfluences(const std::vector<WideVertex>& wide, float tolerance,
                        GltfImportReport* report, Character* c);

// ---- gltf_variations.cpp: parts into variation groups (sub-meshes), their LODs merged.
/// Builds c->mesh.sub_meshes, indices and vertex_materials from `primitives`
/// (GltfImportDesc::variations and variation_groups) and reports parts and groups.
Status groupVariations(const std::vector<ImportedPrimitive>& primitives,
                       const GltfImportDesc& desc, GltfImportReport* report, Character* c);

// ---- gltf_material.cpp: materials (index 0 a default white) and base colour images.
void convertMaterials(const tinygltf::Model& m, GltfImportReport* report, Character* c);

// ---- gltf_animation.cpp: clips of the skeleton's joints and of the morph targets' weights.
/// Weights channels of nodes with morph targets (`node_targets`) become Clip::morph_tracks;
/// others are skipped with a warning.
Status convertClips(const tinygltf::Model& m, const GltfImportDesc& desc, const SkinBinding& skin,
                    const std::vector<NodeMorphTargets>& node_targets, GltfImportReport* report,
                    Character* c);

}  // namespace si::detail
