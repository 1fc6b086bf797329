// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Compiling and linking: every program of the catalog (program_catalog.h), built once by
// Renderer::init() with the built-in material, each with the locations of the shared uniforms
// it declares; and per host material (Renderer::addMaterial) the programs that take it.

#include <glad/gl.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "gl/programs/material_check.h"
#include "gl/programs/program_catalog.h"
#include "si/core/status.h"

namespace si::detail {

inline constexpr GLuint kNoObject = 0;

/// A linked program and which of the shared uniforms it declares (-1: absent; setting an
/// absent location is GL_INVALID_OPERATION).
struct Program {
  GLuint id = kNoObject;
  GLint view_projection = -1, light_direction = -1, custom_layers = -1;
  /// The LOD of the batch drawn (SiSurface.lod) on the paths that draw one LOD a call.
  GLint lod = -1;
  /// Motion vectors: the crowd's last and previous update cameras' view-projections.
  GLint motion_view_projection = -1, previous_view_projection = -1;
  /// SI_INSTANCE_HANDLE's baselines: the drawn instance's handle (u_instance_handle).
  GLint instance_handle = -1;
  /// drawCrowd's batch's first slot (shaders/batch_slot.glsl), where the program reads its
  /// composed rows, previous indices or instance handles.
  GLint batch_slot = -1;
  /// The impostor fragment stage's surface value (u_impostor_surface; impostor_surface.h).
  GLint impostor_surface = -1;
};

/// Compiles one shader: kBackend with the driver's log on failure.
Status compileShader(GLenum type, const std::string& source, const char* name, GLuint* out);

/// Mesh features that change the programs drawing a character (bits of
/// ProgramTable::features): texture coordinates 1 or colours; a second set of influences;
/// morph targets.
inline constexpr uint32_t kMeshVertexWords = 1;
inline constexpr uint32_t kMeshEightInfluences = 2;
inline constexpr uint32_t kMeshMorphTargets = 4;
/// The features that change how vertices are skinned (skinsVertices() programs).
inline constexpr uint32_t kMeshSkinFeatures = kMeshEightInfluences | kMeshMorphTargets;

/// The catalog's programs, compiled and linked.
class ProgramSet {
 public:
  ProgramSet() = default;
  ProgramSet(const ProgramSet&) = delete;
  ProgramSet& operator=(const ProgramSet&) = delete;
  ~ProgramSet() = default;  // release() needs the context: the renderer calls it.

  /// Builds every program of the catalog with `config`'s defines and the built-in material
  /// (material 0). kBackend with the driver's log (and nothing kept) when one fails to compile
  /// or link.
  Status build(const ShaderConfig& config);
  /// Builds the programs that take `material` (takesMaterial()) and keeps them as material
  /// `*index` (1 and up). kBackend with the driver's log naming the material and the program
  /// when one fails to compile or link; kInvalidArgument when the material declares a
  /// resource the library's draws cannot leave alone (material_check.h). Nothing kept then.
  Status addMaterial(const MaterialSource& material, uint32_t* index);
  /// Builds, once, the depth-only programs of alpha-masked characters: surface.frag.glsl with
  /// SI_DEPTH_ONLY and a material that writes nothing, so the surface's alpha-mask discard
  /// (glTF MASK) alone cuts the depth; for meshes with `features` (their kMeshSkinFeatures:
  /// 8 influences, morph targets). kBackend with the driver's log when one fails.
  Status buildMaskedDepth(uint32_t features = 0);
  /// Builds, once for `material` (0: the built-in one; a host material also needs the built-in
  /// variants of the programs it does not change) and mesh `features` (kMeshVertexWords,
  /// kMeshEightInfluences or both), the variants of the programs a feature changes, drawn for
  /// characters whose meshes have those features: those that readsVertexWords() with
  /// ShaderConfig::vertex_words (texture coordinates 1 or colours; the others write no output
  /// for them) and those that skinsVertices() with ShaderConfig::eight_influences and
  /// morph_targets (and, for the latter, the layer compose passes, composesLayers(), and the
  /// depth-only programs of alpha-masked characters: buildMaskedDepth()).
  /// kBackend with the driver's log when one fails; kInvalidArgument for an unknown material.
  Status buildMeshVariants(uint32_t material, uint32_t features);
  /// Deletes every program (context current). Idempotent.
  void release();

  /// Program `id` of the built-in material.
  const Program& operator[](ProgramId id) const { return programs_[size_t(id)]; }
  /// Program `id` drawing material `material` (0: the built-in; the built-in program where
  /// the material does not change it, or for an unknown material) for a character with
  /// alpha-masked materials or without: the depth-only programs of a masked character
  /// discard by its mask (buildMaskedDepth), unless the material's own do (depth_discard);
  /// for a character whose mesh has `features` (kMeshVertexWords, kMeshEightInfluences), their
  /// variant where buildMeshVariants() built one.
  const Program& get(ProgramId id, uint32_t material, bool alpha_masked,
                     uint32_t features = 0) const;
  /// Materials, the built-in one included.
  uint32_t materialCount() const { return uint32_t(materials_.size()) + 1; }
  /// Whether `material`'s programs read the drawn instance's handle
  /// (MaterialDesc::instance_handle): the draws then hand it over (shaders/instance_handle.glsl).
  bool readsInstanceHandle(uint32_t material) const {
    return material != 0 && material <= materials_.size() &&
           materials_[material - 1]->source.instance_handle;
  }

 private:
  struct MaterialPrograms {
    MaterialSource source;
    std::array<Program, kProgramCount> programs{};
  };
  ShaderConfig config_;
  LibraryBindings bindings_;  // Of every built-in program (desktop GL): what materials avoid.
  std::array<Program, kProgramCount> programs_{};
  // buildMaskedDepth's (kDepth ids only), by skin features (kMeshSkinFeatures bits).
  std::array<std::array<Program, kProgramCount>, 8> masked_depth_{};
  // buildMeshVariants's, by mesh features (index 0 unused) and material (0: the built-in one;
  // a host material's hold only the programs it changes).
  std::array<std::vector<std::array<Program, kProgramCount>>, 8> variants_;
  std::vector<std::unique_ptr<MaterialPrograms>> materials_;  // Material index - 1.
};

/// The programs a draw uses: the renderer's set seen through one character's material.
struct ProgramTable {
  const ProgramSet* set = nullptr;
  uint32_t material = 0;
  bool alpha_masked = false;  ///< The character has alpha-masked materials.
  uint32_t features = 0;      ///< The character's mesh features (kMeshVertexWords, ...).
  const Program& operator[](ProgramId id) const {
    return set->get(id, material, alpha_masked, features);
  }
};

}  // namespace si::detail
