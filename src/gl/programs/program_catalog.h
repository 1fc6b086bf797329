// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Every GL program of the back-end: which shader files and defines make each one. The one
// place that says how a program's source is put together, used by ProgramSet (to compile them)
// and by the offline shader check (tests/render/glsl_check_test.cpp, glslang). No GL here.

#include <cstdint>
#include <string>

#include "si/core/status.h"

namespace si::detail {

enum class ProgramId : uint8_t {
  kSkinned = 0,        ///< Vertex-shader skinning, shaded.
  kDepthOnly,          ///< Vertex-shader skinning, depth only.
  kRigid,              ///< Rigid instancing of the bind pose (the floor baseline).
  kTraditional,        ///< One character per draw, joint matrices in a uniform block.
  kCapture,            ///< Vertex-shader skinning with the model-space position captured.
  kPreSkinned,         ///< The CPU-skinning baseline's draw of CPU-skinned vertices.
  kComputeSkin,        ///< Compute pre-skinning's skinning pass.
  kPulled,             ///< Compute pre-skinning's vertex-pulling draw.
  kGpuDrivenSkinned,   ///< GPU-driven culling's draw (records through bucket entries).
  kCull,               ///< GPU-driven culling: selection and records.
  kCullCommands,       ///< GPU-driven culling: prefix sums into indirect commands.
  kCullScatter,        ///< GPU-driven culling: bucket entries.
  kGpuSkin,            ///< GPU-driven pre-skinning (dispatched indirectly).
  kGpuPulled,          ///< GPU-driven pre-skinned draw (vertex pulling through entries).
  kHizCopy,            ///< Occlusion culling: depth into the pyramid's level 0.
  kHizReduce,          ///< Occlusion culling: one pyramid level from the one below.
  kSkinnedMotion,      ///< kSkinned, also writing motion vectors (RendererDesc::motion_vectors).
  kComputeSkinMotion,  ///< kComputeSkin, also skinning the previous position.
  kPulledMotion,       ///< kPulled, also writing motion vectors.
  kSkinnedLayers,      ///< kSkinned with layered animation (overlays on masks).
  kComputeSkinLayers,  ///< kComputeSkin with layered animation.
  kDepthOnlyLayers,    ///< kDepthOnly with layered animation.
  kGpuDrivenSkinnedLayers,          ///< kGpuDrivenSkinned with layered animation.
  kGpuSkinLayers,                   ///< kGpuSkin with layered animation.
  kSkinnedMotionLayers,             ///< kSkinnedMotion with layered animation.
  kComputeSkinMotionLayers,         ///< kComputeSkinMotion with layered animation.
  kGpuDrivenSkinnedMotion,          ///< kGpuDrivenSkinned, also writing motion vectors.
  kGpuSkinMotion,                   ///< kGpuSkin, also skinning the previous position.
  kGpuPulledMotion,                 ///< kGpuPulled, also writing motion vectors.
  kGpuDrivenSkinnedMotionLayers,    ///< kGpuDrivenSkinnedMotion with layered animation.
  kGpuSkinMotionLayers,             ///< kGpuSkinMotion with layered animation.
  kGpuDrivenDepthOnly,              ///< kGpuDrivenSkinned, depth only (shadow views).
  kGpuDrivenDepthOnlyLayers,        ///< kGpuDrivenDepthOnly with layered animation.
  kGpuPulledDepthOnly,              ///< kGpuPulled, depth only.
  kImpostorCapture,                 ///< kSkinned writing the impostor atlas's three layers.
  kImpostor,                        ///< Impostor quads, records from the instance block.
  kImpostorDepthOnly,               ///< kImpostor, depth only.
  kGpuDrivenImpostor,               ///< Impostor quads, records through bucket entries.
  kGpuDrivenImpostorDepthOnly,      ///< kGpuDrivenImpostor, depth only.
  kLayerCompose,                    ///< Layered animation: each batch's masked rows composed.
  kLayerComposeMotion,              ///< kLayerCompose, also the previous records' rows.
  kSkinnedComposed,                 ///< kSkinnedLayers reading the composed rows.
  kSkinnedMotionComposed,           ///< kSkinnedMotionLayers reading the composed rows.
  kDepthOnlyComposed,               ///< kDepthOnlyLayers reading the composed rows.
  kGpuLayerCompose,                 ///< kLayerCompose over the cull pass's visible records.
  kGpuLayerComposeMotion,           ///< kGpuLayerCompose, also the previous records' rows.
  kGpuDrivenSkinnedComposed,        ///< kGpuDrivenSkinnedLayers reading the composed rows.
  kGpuDrivenSkinnedMotionComposed,  ///< kGpuDrivenSkinnedMotionLayers reading them.
  kGpuDrivenDepthOnlyComposed,      ///< kGpuDrivenDepthOnlyLayers reading them.
  kComputeSkinComposed,             ///< kComputeSkinLayers reading the composed rows.
  kComputeSkinMotionComposed,       ///< kComputeSkinMotionLayers reading them.
  kGpuSkinComposed,                 ///< kGpuSkinLayers reading them.
  kGpuSkinMotionComposed,           ///< kGpuSkinMotionLayers reading them.
  kUploadScatter,                   ///< Staged uploads into place (resources/upload_ring.h).
  kHizCopyMultisample,              ///< kHizCopy from a multisampled depth (farthest sample).
  kPulledTangents,                  ///< kPulled with the tangent ring (a character's tangents).
  kPulledMotionTangents,            ///< kPulledMotion with the tangent ring.
  kGpuPulledTangents,               ///< kGpuPulled with the tangent ring.
  kGpuPulledMotionTangents,         ///< kGpuPulledMotion with the tangent ring.
  kImpostorQuads,                   ///< GPU-driven impostors: each quad once, before the draw.
  kImpostorCoverage,                ///< An impostor atlas level's covered extents (si::vk's).
  kImpostorCoverageRects,           ///< The extents packed into the clip table (si::vk's).
  kImpostorResolve,                 ///< An impostor atlas's level 0 from its supersampled capture.
  kCount
};
inline constexpr size_t kProgramCount = size_t(ProgramId::kCount);

enum class ShaderStage : uint8_t { kVertex = 0, kFragment, kCompute };
inline const char* shaderStageName(ShaderStage stage) {
  return stage == ShaderStage::kVertex     ? "vertex"
         : stage == ShaderStage::kFragment ? "fragment"
                                           : "compute";
}

/// How one program is made: each stage's file (null when the program has no such stage), the
/// defines before it, and the varying transform feedback captures (or null).
struct ProgramSpec {
  const char* name;
  const char* defines;
  const char* vertex;
  const char* fragment;
  const char* compute;
  const char* capture_varying;

  const char* file(ShaderStage stage) const {
    return stage == ShaderStage::kVertex ? vertex : stage == ShaderStage::kFragment ? fragment
                                                                                      : compute;
  }
};
const ProgramSpec& programSpec(ProgramId id);

/// The vertex-shader skinning program of drawCrowd (`gpu_driven` false) or of the GPU-driven
/// path: depth only or shaded, with motion vectors (shaded only), overlays walked per vertex
/// (`layers`) or read from the compose pass's rows (`composed`, with `layers`).
ProgramId skinningProgram(bool gpu_driven, bool depth_only, bool motion, bool layers,
                          bool composed);

/// The pre-skinning (compute) program of drawCrowd's compute path (`gpu_driven` false) or of
/// the GPU-driven path: with previous positions (`motion`), overlays walked per vertex
/// (`layers`) or read from the compose pass's rows (`composed`, with `layers`).
ProgramId preSkinningProgram(bool gpu_driven, bool motion, bool layers, bool composed);

/// The shaded vertex-pulling draw of the pre-skinned ring for drawCrowd's compute path
/// (`gpu_driven` false) or the GPU-driven path: with motion vectors (`motion`), reading the
/// tangent ring for a character with tangents (`tangents`; without, the tangent costs no
/// varying).
ProgramId pullingProgram(bool gpu_driven, bool motion, bool tangents);

/// What a program's fragment stage does with the draw's material (si::MaterialDesc).
enum class MaterialUse : uint8_t {
  kNone = 0,  ///< No material: compute passes, transform feedback, the impostors' coverage test.
  kShaded,    ///< The fragment stage hands its surface to the material (surface.frag.glsl,
              ///< impostor.frag.glsl): one such program per material.
  kDepth,     ///< Depth only: depth.frag.glsl, or for a material that discards
              ///< (MaterialDesc::depth_discard) surface.frag.glsl with SI_DEPTH_ONLY and it.
  kCapture,   ///< The impostor capture: surface.frag.glsl with the capture's own material.
};
MaterialUse materialUse(ProgramId id);

/// A material's GLSL as the programs compile it (si::MaterialDesc's).
struct MaterialSource {
  std::string name;
  std::string text;
  bool depth_discard = false;
  bool instance_handle = false;  ///< SI_INSTANCE_HANDLE in both stages of the programs it takes.
};

/// Whether program `id` differs between `material` and the built-in material: its fragment
/// stage calls the material (kShaded), or discards by it (kDepth, `material.depth_discard`).
bool takesMaterial(ProgramId id, const MaterialSource& material);

/// The values of the defines every program gets.
struct ShaderConfig {
  uint32_t max_instances = 0;  ///< SI_MAX_INSTANCES: records in the instance uniform block.
  uint32_t max_joints = 0;     ///< SI_MAX_JOINTS: joints in the traditional path's block.
  /// The ES profile: "#version 300 es" (GLSL ES 3.00, WebGL 2's), default precisions and
  /// SI_MAX_MATERIALS (kEsMaxMaterials); only esProgram() programs are built.
  bool es = false;
  /// SI_VERTEX_WORDS: the mesh's optional vertex words (texture coordinates 1, colours) reach
  /// the surface. Only the variants drawn for characters whose meshes have them
  /// (readsVertexWords()): without the define the vertex stages write no output for them.
  bool vertex_words = false;
  /// SI_EIGHT_INFLUENCES: the mesh's second set of influences (SkinnedMesh::joints1/weights1,
  /// attributes 10 and 11, or the pre-skinning source's words after the fixed ones) is
  /// skinned too. Only the variants drawn for such characters (skinsVertices()).
  bool eight_influences = false;
  /// SI_MORPH_TARGETS: the mesh's morph targets (its morph word, attribute 12 or the
  /// pre-skinning source's last word; the morph texture; si_morph.glsl) are added before
  /// skinning. Only the variants drawn for such characters (skinsVertices(), composesLayers()).
  bool morph_targets = false;
  /// SI_MASK_BINDING: the storage binding of the layer mask table (si_skinning.glsl); 0 leaves
  /// its default, 8. si::vk's GPU-driven programs move it (kDrivenMaskBinding): in its one
  /// descriptor set of the compute passes, 8 holds the bucket ranges, which si::gl rebinds.
  uint32_t mask_binding = 0;
};

/// Whether program `id` comes in a variant for meshes with optional vertex words
/// (ShaderConfig::vertex_words): it hands a mesh's surface to a material
/// (surface.frag.glsl, shaded or the impostor capture).
bool readsVertexWords(ProgramId id);
/// Whether program `id` comes in a variant for meshes with 8 influences
/// (ShaderConfig::eight_influences): it skins the mesh's vertices (skinned.vert.glsl but the
/// rigid floor, and the pre-skinning passes).
bool skinsVertices(ProgramId id);
/// Whether program `id` also comes in a variant for meshes with morph targets
/// (ShaderConfig::morph_targets) without skinning vertices: the layer compose passes, which
/// compose each overlaid record's morph weights (layer_compose.comp.glsl).
bool composesLayers(ProgramId id);

/// Entries of the material table's uniform block on the ES profile (material_common.glsl):
/// 32 bytes each, 8 KiB. A character with more materials is refused there (kLimitExceeded).
inline constexpr uint32_t kEsMaxMaterials = 256;

/// Whether the ES profile has program `id`: the vertex-shader path's programs (skinned,
/// depth-only, rigid). The others need storage buffers, compute or transform feedback.
bool esProgram(ProgramId id);

/// A uniform block or sampler of the catalog's shaders and the binding (texture unit for a
/// sampler) the desktop shaders give it with a layout qualifier; GLSL ES 3.00 has none, so the
/// ES profile sets these after linking (ProgramSet).
struct EsBinding {
  const char* name;
  bool sampler;
  uint32_t binding;
};
/// The ES profile's programs' blocks and samplers, `*count` of them.
const EsBinding* esBindings(size_t* count);

/// The source of one stage as the driver compiles it: "#version 450 core" (or the ES
/// profile's "#version 300 es" and precisions), the shared defines, the program's defines, then
/// the stage's file (for a program that takes a material asking for the instance handle,
/// SI_INSTANCE_HANDLE in its vertex and fragment stages), and for a fragment stage that takes
/// a material (materialUse()) the
/// material's text after "#line 1 1", so a compiler names the material's own lines as those
/// of source string 1. `material` null: the built-in material (builtin_material.glsl).
/// kInvalidArgument when the program has no such stage; kNotFound when its file was not
/// embedded.
Status assembleStage(ProgramId id, ShaderStage stage, const ShaderConfig& config,
                     std::string* out, const MaterialSource* material = nullptr);

}  // namespace si::detail
