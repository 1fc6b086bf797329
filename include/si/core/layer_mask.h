// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Layered (masked) animation: an overlay clip drives the joints of a mask (for example the
/// right arm waving) over a base clip that drives every joint (walking). The palette stores
/// model-space skinning matrices, so taking the overlay's matrix for a masked joint would detach
/// the branch from the base pose: the arm would wave where the overlay clip's chest is, not
/// where the walking chest is. Done correctly, in local space, a masked joint takes the
/// overlay's local transforms from the branch root down, attached to the base pose's branch
/// parent (the anchor a). In skinning matrices (S = global * inverse bind) that is exactly
///
///   S_j = S_base(a) * inverse(S_overlay(a)) * S_overlay(j)
///
/// (the bind matrices cancel), which the shader computes from the palette as it stands: no
/// extra baking. A weight w in (0, 1) blends as the reference (evaluateLayeredPose) does, each
/// masked joint's local transform a fraction w of the way to the overlay's, composed from the
/// anchor down: the palette gives each stored joint's transform relative to its nearest stored
/// masked ancestor (inverse(S_parent) * S_joint), which si::localBlend blends as the local
/// transform it is seen through the bind matrices (the mask keeps each slot's bind-pose origin
/// for that). What remains is the palette's sampling, and where a masked joint is not stored
/// (no vertex is weighted to it) its transform is blended together with its stored child's;
/// measureLayeredError (si::bake) reports the difference.
///
/// Usage:
/// \code
///   si::LayerMask arm;
///   si::Status s = si::buildLayerMask(character.skeleton, palette, "right arm",
///                                     {"r_clavicle"}, &arm);
///   crowd.addLayerMask(arm, &mask_id);  // si::CrowdManager (a handful per crowd)
/// \endcode

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/baked_palette.h"
#include "si/core/clip.h"
#include "si/core/reference_evaluator.h"
#include "si/core/skeleton.h"
#include "si/core/skinned_mesh.h"
#include "si/core/span.h"
#include "si/core/status.h"

namespace si {

/// A mask of one character (one palette): whole branches of joints, each a joint and all its
/// descendants, and morph targets.
struct LayerMask {
  /// slot_anchor value of a palette slot outside the mask.
  static constexpr int32_t kNotInMask = -2;
  /// slot_anchor value of a masked slot whose branch root has no parent: the overlay's matrix
  /// is taken as it is (its anchor is the model origin).
  static constexpr int32_t kModelAnchor = -1;

  std::string name;
  /// Per palette slot: kNotInMask, kModelAnchor, or the palette slot of the anchor (the parent
  /// of the slot's branch root), which is itself outside the mask.
  std::vector<int32_t> slot_anchor;
  /// slot_parent value of a slot outside the mask or of one with no masked ancestor stored.
  static constexpr int32_t kNoParentSlot = -1;
  /// Per palette slot: for a masked slot, the palette slot of its nearest masked ancestor that
  /// the palette stores, else kNoParentSlot. Between weights 0 and 1 the blend follows this
  /// chain to turn each joint the way its ancestors turn (a hand whose overlay is 190 degrees
  /// from the base follows the arm rather than swinging the other way through the body).
  std::vector<int32_t> slot_parent;
  /// The skeleton joints in the mask, increasing (stored in the palette or not): what the
  /// reference blends.
  std::vector<uint32_t> joints;
  /// Per palette slot: its joint's bind-pose origin in model space (the translation of the
  /// inverse of its inverse bind matrix), the pivot si::localBlend blends about. Only masked
  /// slots' values are read.
  std::vector<glm::vec3> slot_bind_origin;
  /// The morph targets (indices into SkinnedMesh::morph_targets) the overlay moves, increasing:
  /// there its clip's weights replace the base's, blended by the overlay's weight; the other
  /// targets keep the base's weights. Empty by default; a mask may hold targets alone
  /// (buildMorphTargetMask: an expression, a viseme or a blink over whatever the body plays).
  std::vector<uint32_t> morph_targets;

  /// Whether palette slot `slot` is in the mask.
  bool contains(uint32_t slot) const {
    return slot < slot_anchor.size() && slot_anchor[slot] != kNotInMask;
  }
  /// Whether the overlay moves morph target `target`.
  bool movesTarget(uint32_t target) const {
    return std::binary_search(morph_targets.begin(), morph_targets.end(), target);
  }
  /// Checks it against `palette`: one entry per palette slot, each kNotInMask, kModelAnchor or
  /// a slot outside the mask, at least one slot or morph target in it (kInvalidArgument);
  /// morph targets increasing and below the palette's morph_target_count (kInvalidArgument);
  /// parent slots masked
  /// and without cycles (kInvalidArgument); one bind origin per slot (kInvalidArgument), the
  /// masked slots' finite (kNotFinite); joints increasing,
  /// below the palette's skeleton size, and exactly the skeleton joints of the masked slots
  /// among them (kInvalidArgument).
  Status validate(const BakedPalette& palette) const;
};

/// Builds the mask of the branches rooted at the joints named `branch_roots` (each with all
/// its descendants). kInvalidArgument for a null `out` or no names; kNotFound naming an unknown
/// joint; kInvalidArgument when the skeleton does not validate or is not the palette's (joint
/// count); kNotFound when a branch's anchor (its root's parent) drives vertices outside the
/// palette, i.e. is not stored in it: the shader needs its matrix (bake a palette that stores
/// it, or pick the anchor's parent's branch). Nothing is written on failure.
Status buildLayerMask(const Skeleton& skeleton, const BakedPalette& palette,
                      const std::string& name, const std::vector<std::string>& branch_roots,
                      LayerMask* out);

/// The same from an explicit list of joint names, which must hold every descendant of each
/// (kInvalidArgument naming the first listed joint whose child is missing): a set of branches.
Status buildLayerMaskFromJoints(const Skeleton& skeleton, const BakedPalette& palette,
                                const std::string& name, const std::vector<std::string>& joints,
                                LayerMask* out);

/// The mask of every joint (the branches of the skeleton's roots, each anchored on the model):
/// a blend space's mask (si::BlendSpace), whose upper clip then composes on the whole
/// character, the local-space blend of two clips. Fails as buildLayerMask() does.
Status buildFullBodyMask(const Skeleton& skeleton, const BakedPalette& palette,
                         const std::string& name, LayerMask* out);

/// The mask of the morph targets named `target_names` (MorphTarget::name in `mesh`) alone, no
/// joint: an overlay on it moves those targets by its clip's weights (an expression, a viseme,
/// a blink) and leaves every joint to the base clip. kInvalidArgument for a null `out`, no
/// names, or a palette not baked with the mesh's targets (layout.morph_target_count);
/// kNotFound naming a target the mesh does not hold. Nothing is written on failure.
Status buildMorphTargetMask(const SkinnedMesh& mesh, const BakedPalette& palette,
                            const std::string& name, const std::vector<std::string>& target_names,
                            LayerMask* out);

/// The mask table si_skinning.glsl reads (SI_LAYERS, storage binding SI_MASK_BINDING): the
/// palette slot count, the morph words per mask (w: enough 32-bit words for the highest target
/// any mask moves; 0 when none does), then for each mask in order its slot_anchor, its
/// slot_parent, its slot_bind_origin (x, y, z per slot, each float's bits) and w words of
/// morph target bits (target t: bit t % 32 of word t / 32) (`masks` all of one palette, as a
/// crowd's are). {0, 0} for no masks.
std::vector<int32_t> layerMaskTable(Span<const LayerMask> masks);

/// A pose's skinning matrix by palette slot (affine: last row 0 0 0 1), as emulateLayeredMatrix
/// reads the base and the overlay.
using SlotMatrices = std::function<glm::mat4(uint32_t slot)>;

/// The layered skinning matrix the shader computes for palette slot `slot` of `mask` (float):
/// base(slot) outside the mask or at weight 0; at weight 1
/// base(a) * inverse(overlay(a)) * overlay(slot), a the slot's anchor (the identity for
/// kModelAnchor); between them, the slot's transform relative to its nearest masked ancestor
/// (slot_parent, followed to the anchor) blended by si::localBlend for each link of the chain
/// and composed on base(a): the reference's local-space blend where every masked joint is
/// stored. `mask` is assumed valid (LayerMask::validate) for the palette `base` and `overlay`
/// read; a slot past it is treated as outside it.
glm::mat4 emulateLayeredMatrix(const LayerMask& mask, uint32_t slot, float weight,
                               const SlotMatrices& base, const SlotMatrices& overlay);

/// One overlay of a chain (emulateLayeredChain): its pose and its weight over what the layers
/// before it composed.
struct LayerPose {
  SlotMatrices matrices;
  float weight = 0.0f;
};

/// Layers composed one after another on one mask (a blend of up to four clips, si::BlendSpace):
/// layer k blends each masked link's local transform a fraction `weight` of the way from what
/// the base and layers 0..k-1 gave to its own. One layer is emulateLayeredMatrix(). Layers at
/// weight 0 are skipped; a layer at weight 1 replaces all before it, and when it is the last
/// one drawn its branch is attached to the base's anchor as emulateLayeredMatrix() does at
/// weight 1. Outside the mask, or with every weight 0, base(slot).
glm::mat4 emulateLayeredChain(const LayerMask& mask, uint32_t slot, const SlotMatrices& base,
                              Span<const LayerPose> layers);

/// The palette slots of `slot`'s masked ancestors in `mask`, parent first (slot_parent followed
/// to kNoParentSlot, at most the mask's slot count): the chain emulateLayeredMatrix follows.
std::vector<uint32_t> layerChain(const LayerMask& mask, uint32_t slot);

/// The reference: `base` at clip time `base_time` on every joint, and on the mask's joints the
/// local transforms blended towards `overlay` at `overlay_time` by `weight` (translation and
/// scale lerped, rotation slerped along the shorter arc), composed in double. Times are mapped
/// by each clip's loop mode (clipLocalTime). Fails as evaluatePose() does, and kInvalidArgument
/// for a weight outside [0, 1] or a mask joint past the skeleton.
Status evaluateLayeredPose(const Skeleton& skeleton, const Clip& base, double base_time,
                           const Clip& overlay, double overlay_time, const LayerMask& mask,
                           double weight, ReferencePose* pose);

/// One overlay of evaluateLayeredChainPose: a clip at a time, and its weight over what the layers
/// before it composed.
struct LayerSample {
  const Clip* clip = nullptr;
  double time = 0.0;
  double weight = 0.0;
};

/// The reference of a chain of layers on one mask: `base` at `base_time` on every joint, then
/// for each layer in order the mask's local transforms blended towards it by its weight (as
/// evaluateLayeredPose blends one). Fails as evaluateLayeredPose() does, and kInvalidArgument
/// for a null clip.
Status evaluateLayeredChainPose(const Skeleton& skeleton, const Clip& base, double base_time,
                                Span<const LayerSample> layers, const LayerMask& mask,
                                ReferencePose* pose);

}  // namespace si
