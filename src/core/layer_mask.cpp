// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Layered animation's joint masks, the shader's layered matrix and the local-space reference.
#include "si/core/layer_mask.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/quaternion.hpp>

#include "core/str_cat.h"
#include "si/core/local_blend.h"

namespace si {

using detail::strCat;

namespace {

// The mask of the joints flagged in `in_mask` (closed under descendants), with each masked
// joint's anchor: the parent of its branch root.
Status finishMask(const Skeleton& skeleton, const BakedPalette& palette, const std::string& name,
                  const std::vector<uint8_t>& in_mask, LayerMask* out) {
  const size_t n = skeleton.jointCount();
  LayerMask m;
  m.name = name;
  m.slot_anchor.assign(palette.palette_joints.size(), LayerMask::kNotInMask);
  m.slot_parent.assign(palette.palette_joints.size(), LayerMask::kNoParentSlot);
  m.slot_bind_origin.assign(palette.palette_joints.size(), glm::vec3(0.0f));
  std::vector<int32_t> anchor_joint(n, Skeleton::kNoParent);
  // Per joint: the palette slot of the nearest masked ancestor (or itself) that is stored.
  std::vector<int32_t> stored_in_mask(n, LayerMask::kNoParentSlot);
  for (size_t j = 0; j < n; ++j) {
    if (!in_mask[j]) continue;
    m.joints.push_back(uint32_t(j));
    const int32_t parent = skeleton.parents[j];
    anchor_joint[j] = parent >= 0 && in_mask[size_t(parent)] ? anchor_joint[size_t(parent)] : parent;
    const int32_t slot = palette.skeleton_to_palette[j];
    const int32_t up = parent >= 0 && in_mask[size_t(parent)] ? stored_in_mask[size_t(parent)]
                                                             : LayerMask::kNoParentSlot;
    stored_in_mask[j] = slot >= 0 ? slot : up;
    if (slot < 0) continue;  // Drives no vertex.
    m.slot_parent[size_t(slot)] = up;
    m.slot_bind_origin[size_t(slot)] = glm::vec3(glm::inverse(skeleton.inverse_bind_matrices[j])[3]);
    const int32_t a = anchor_joint[j];
    if (a < 0) {
      m.slot_anchor[size_t(slot)] = LayerMask::kModelAnchor;
      continue;
    }
    const int32_t anchor_slot = palette.skeleton_to_palette[size_t(a)];
    if (anchor_slot < 0)
      return {StatusCode::kNotFound,
              strCat("layer mask '", name, "': joint '", skeleton.joint_names[j],
                     "' hangs from '", skeleton.joint_names[size_t(a)],
                     "', which the palette does not store (no vertex is weighted to it); the ",
                     "shader needs its matrix: mask its parent's branch instead")};
    m.slot_anchor[size_t(slot)] = anchor_slot;
  }
  const Status s = m.validate(palette);
  if (!s.isOk()) return {s.code(), strCat("layer mask '", name, "': ", s.message())};
  *out = std::move(m);
  return Status::ok();
}

Status checkInputs(const Skeleton& skeleton, const BakedPalette& palette, const void* out,
                   size_t names) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "layer mask: null output"};
  if (names == 0) return {StatusCode::kInvalidArgument, "layer mask: no joints named"};
  const Status s = skeleton.validate();
  if (!s.isOk()) return {StatusCode::kInvalidArgument, "layer mask: " + s.message()};
  if (palette.skeleton_to_palette.size() != skeleton.jointCount())
    return {StatusCode::kInvalidArgument,
            strCat("layer mask: the skeleton has ", skeleton.jointCount(),
                   " joints, the palette was baked for ", palette.skeleton_to_palette.size())};
  return Status::ok();
}

// Mask `name`'s joints named `joints`, flagged in `in_mask` (one flag per skeleton joint);
// kNotFound for a name the skeleton does not hold.
Status markJoints(const Skeleton& skeleton, const std::vector<std::string>& joints,
                  const std::string& name, std::vector<uint8_t>* in_mask) {
  in_mask->assign(skeleton.jointCount(), 0);
  for (const std::string& joint : joints) {
    const int32_t j = skeleton.findJoint(joint);
    if (j < 0)
      return {StatusCode::kNotFound,
              strCat("layer mask '", name, "': no joint named '", joint, "'")};
    (*in_mask)[size_t(j)] = 1;
  }
  return Status::ok();
}

}  // namespace

Status LayerMask::validate(const BakedPalette& palette) const {
  const size_t slots = palette.palette_joints.size();
  if (slot_anchor.size() != slots)
    return {StatusCode::kInvalidArgument,
            strCat("the mask has ", slot_anchor.size(), " slots, the palette ", slots)};
  size_t masked = 0;
  for (size_t s = 0; s < slots; ++s) {
    const int32_t a = slot_anchor[s];
    if (a == kNotInMask) continue;
    ++masked;
    if (a == kModelAnchor) continue;
    if (a < 0 || size_t(a) >= slots || slot_anchor[size_t(a)] != kNotInMask)
      return {StatusCode::kInvalidArgument,
              strCat("slot ", s, "'s anchor ", a, " is not a palette slot outside the mask")};
  }
  if (masked == 0 && morph_targets.empty())
    return {StatusCode::kInvalidArgument, "no palette slot and no morph target is in the mask"};
  for (size_t i = 0; i < morph_targets.size(); ++i)
    if (morph_targets[i] >= palette.layout.morph_target_count ||
        (i > 0 && morph_targets[i] <= morph_targets[i - 1]))
      return {StatusCode::kInvalidArgument,
              strCat("the mask's morph targets are not increasing targets below the palette's ",
                     palette.layout.morph_target_count)};
  if (slot_parent.size() != slots)
    return {StatusCode::kInvalidArgument,
            strCat("the mask has ", slot_parent.size(), " parent slots, the palette ", slots)};
  for (size_t s = 0; s < slots; ++s) {
    const int32_t p = slot_parent[s];
    if (p == kNoParentSlot) continue;
    if (p < 0 || size_t(p) >= slots || size_t(p) == s || slot_anchor[s] == kNotInMask ||
        slot_anchor[size_t(p)] == kNotInMask)
      return {StatusCode::kInvalidArgument,
              strCat("slot ", s, "'s parent slot ", p, " is not another slot of the mask")};
    size_t steps = 0;  // The shader follows the chain: it must end.
    for (int32_t up = p; up >= 0; up = slot_parent[size_t(up)])
      if (++steps > slots)
        return {StatusCode::kInvalidArgument, strCat("slot ", s, "'s parent slots form a cycle")};
  }
  if (slot_bind_origin.size() != slots)
    return {StatusCode::kInvalidArgument,
            strCat("the mask has ", slot_bind_origin.size(), " bind origins, the palette ", slots, " slots")};
  for (size_t s = 0; s < slots; ++s) {
    const glm::vec3& o = slot_bind_origin[s];
    if (slot_anchor[s] != kNotInMask && !(std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z)))
      return {StatusCode::kNotFinite,
              strCat("slot ", s, "'s bind origin is not finite (is its inverse bind matrix singular?)")};
  }
  for (size_t i = 0; i < joints.size(); ++i)
    if (joints[i] >= palette.skeleton_to_palette.size() || (i > 0 && joints[i] <= joints[i - 1]))
      return {StatusCode::kInvalidArgument, "the mask's joints are not increasing skeleton joints"};
  size_t stored = 0;
  for (uint32_t j : joints) {
    const int32_t slot = palette.skeleton_to_palette[j];
    if (slot < 0) continue;
    if (slot_anchor[size_t(slot)] == kNotInMask)
      return {StatusCode::kInvalidArgument, strCat("joint ", j, " is listed but its slot is not masked")};
    ++stored;
  }
  if (stored != masked)
    return {StatusCode::kInvalidArgument, "a masked slot's joint is not listed"};
  return Status::ok();
}

namespace {
// buildLayerMask (`branches`: each named joint's whole branch) and buildLayerMaskFromJoints
// (the named joints alone, which must hold whole branches).
Status buildFromNames(const Skeleton& skeleton, const BakedPalette& palette,
                      const std::string& name, const std::vector<std::string>& names, bool branches,
                      LayerMask* out) {
  std::vector<uint8_t> in_mask;
  Status s = checkInputs(skeleton, palette, out, names.size());
  if (s.isOk()) s = markJoints(skeleton, names, name, &in_mask);
  if (!s.isOk()) return s;
  for (size_t j = 0; j < skeleton.jointCount(); ++j) {  // Parents precede children.
    const int32_t p = skeleton.parents[j];
    if (p < 0 || !in_mask[size_t(p)] || in_mask[j]) continue;
    if (branches) {
      in_mask[j] = 1;
      continue;
    }
    return {StatusCode::kInvalidArgument,
            strCat("layer mask '", name, "': '", skeleton.joint_names[size_t(p)],
                   "' is listed but its child '", skeleton.joint_names[j],
                   "' is not (a mask holds whole branches)")};
  }
  return finishMask(skeleton, palette, name, in_mask, out);
}
}  // namespace

Status buildLayerMask(const Skeleton& skeleton, const BakedPalette& palette,
                      const std::string& name, const std::vector<std::string>& branch_roots,
                      LayerMask* out) {
  return buildFromNames(skeleton, palette, name, branch_roots, true, out);
}

Status buildFullBodyMask(const Skeleton& skeleton, const BakedPalette& palette,
                         const std::string& name, LayerMask* out) {
  const Status s = checkInputs(skeleton, palette, out, 1);
  if (!s.isOk()) return s;
  return finishMask(skeleton, palette, name, std::vector<uint8_t>(skeleton.jointCount(), 1), out);
}

Status buildMorphTargetMask(const SkinnedMesh& mesh, const BakedPalette& palette,
                            const std::string& name, const std::vector<std::string>& target_names,
                            LayerMask* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "morph target mask: null output"};
  if (target_names.empty())
    return {StatusCode::kInvalidArgument,
            strCat("morph target mask '", name, "': no targets named")};
  if (palette.layout.morph_target_count != mesh.morph_targets.size())
    return {StatusCode::kInvalidArgument,
            strCat("morph target mask '", name, "': the palette holds the weights of ",
                   palette.layout.morph_target_count, " targets, the mesh has ",
                   mesh.morph_targets.size(), " (bake it with them)")};
  LayerMask m;
  m.name = name;
  const size_t slots = palette.palette_joints.size();
  m.slot_anchor.assign(slots, LayerMask::kNotInMask);
  m.slot_parent.assign(slots, LayerMask::kNoParentSlot);
  m.slot_bind_origin.assign(slots, glm::vec3(0.0f));
  for (const std::string& target : target_names) {
    const auto it = std::find_if(mesh.morph_targets.begin(), mesh.morph_targets.end(),
                                 [&](const MorphTarget& t) { return t.name == target; });
    if (it == mesh.morph_targets.end())
      return {StatusCode::kNotFound,
              strCat("morph target mask '", name, "': no morph target named '", target, "'")};
    m.morph_targets.push_back(uint32_t(it - mesh.morph_targets.begin()));
  }
  std::sort(m.morph_targets.begin(), m.morph_targets.end());
  m.morph_targets.erase(std::unique(m.morph_targets.begin(), m.morph_targets.end()),
                        m.morph_targets.end());
  const Status s = m.validate(palette);
  if (!s.isOk()) return {s.code(), strCat("morph target mask '", name, "': ", s.message())};
  *out = std::move(m);
  return Status::ok();
}

Status buildLayerMaskFromJoints(const Skeleton& skeleton, const BakedPalette& palette,
                                const std::string& name, const std::vector<std::string>& joints,
                                LayerMask* out) {
  return buildFromNames(skeleton, palette, name, joints, false, out);
}

std::vector<uint32_t> layerChain(const LayerMask& mask, uint32_t slot) {
  std::vector<uint32_t> chain;
  int32_t p = slot < mask.slot_parent.size() ? mask.slot_parent[slot] : LayerMask::kNoParentSlot;
  while (p >= 0 && size_t(p) < mask.slot_parent.size() && chain.size() < mask.slot_parent.size()) {
    chain.push_back(uint32_t(p));
    p = mask.slot_parent[size_t(p)];
  }
  return chain;
}

std::vector<int32_t> layerMaskTable(Span<const LayerMask> masks) {
  uint32_t words = 0;
  for (const LayerMask& m : masks)
    if (!m.morph_targets.empty()) words = std::max(words, m.morph_targets.back() / 32u + 1u);
  std::vector<int32_t> table{masks.empty() ? 0 : int32_t(masks[0].slot_anchor.size()),
                             int32_t(words)};
  for (const LayerMask& m : masks) {
    table.insert(table.end(), m.slot_anchor.begin(), m.slot_anchor.end());
    table.insert(table.end(), m.slot_parent.begin(), m.slot_parent.end());
    for (const glm::vec3& o : m.slot_bind_origin)
      for (int k = 0; k < 3; ++k) {
        int32_t bits;
        std::memcpy(&bits, &o[k], sizeof bits);  // The shader reads it with intBitsToFloat.
        table.push_back(bits);
      }
    std::vector<uint32_t> bits(words, 0u);
    for (uint32_t t : m.morph_targets) bits[t / 32u] |= 1u << (t % 32u);
    for (uint32_t b : bits) table.push_back(int32_t(b));
  }
  return table;
}

glm::mat4 emulateLayeredMatrix(const LayerMask& mask, uint32_t slot, float weight,
                               const SlotMatrices& base, const SlotMatrices& overlay) {
  const LayerPose layer{overlay, weight};
  return emulateLayeredChain(mask, slot, base, Span<const LayerPose>(&layer, 1));
}

glm::mat4 emulateLayeredChain(const LayerMask& mask, uint32_t slot, const SlotMatrices& base,
                              Span<const LayerPose> layers) {
  const glm::mat4 base_slot = base(slot);
  if (!mask.contains(slot)) return base_slot;
  // The layers drawn: from the last one at weight 1 (it replaces those before it) on.
  size_t first = 0, drawn = 0, last = 0;
  for (size_t k = 0; k < layers.size(); ++k) {
    if (layers[k].weight >= 1.0f) first = k;
  }
  for (size_t k = first; k < layers.size(); ++k)
    if (layers[k].weight > 0.0f) {
      ++drawn;
      last = k;
    }
  if (drawn == 0) return base_slot;
  const int32_t anchor = mask.slot_anchor[slot];
  const glm::mat4 identity(1.0f);
  const auto at = [&](const SlotMatrices& pose, int32_t s) {
    return s >= 0 ? pose(uint32_t(s)) : identity;
  };
  const glm::mat4 base_anchor = at(base, anchor);
  // A layer at weight 1 drawn alone: its branch attached to the base's anchor.
  if (drawn == 1 && layers[last].weight >= 1.0f)
    return base_anchor * affineInverse(at(layers[last].matrices, anchor)) *
           layers[last].matrices(slot);
  // Each link from the slot up to the anchor (layerChain, then the anchor) blended in local
  // space, layer after layer, composed on the base's anchor.
  const bool from_layer = layers[first].weight >= 1.0f;
  const std::vector<uint32_t> chain = layerChain(mask, slot);
  std::vector<glm::mat4> child(layers.size());
  for (size_t k = first; k < layers.size(); ++k)
    if (layers[k].weight > 0.0f) child[k] = layers[k].matrices(slot);
  glm::mat4 blended(1.0f), child_base = base_slot;
  uint32_t link = slot;
  for (size_t i = 0;; ++i) {
    const bool to_anchor = i == chain.size();
    const int32_t up = to_anchor ? anchor : int32_t(chain[i]);
    const glm::mat4 parent_base = at(base, up);
    const glm::vec3 pivot =
        link < mask.slot_bind_origin.size() ? mask.slot_bind_origin[link] : glm::vec3(0.0f);
    glm::mat4 local = affineInverse(parent_base) * child_base;
    for (size_t k = first; k < layers.size(); ++k) {
      if (!(layers[k].weight > 0.0f)) continue;
      const glm::mat4 parent = at(layers[k].matrices, up);
      const glm::mat4 own = affineInverse(parent) * child[k];
      local = k == first && from_layer ? own : localBlend(local, own, pivot, layers[k].weight);
      child[k] = parent;
    }
    blended = local * blended;
    if (to_anchor) return parent_base * blended;
    link = chain[i];
    child_base = parent_base;
  }
}

namespace {

// evaluateLayeredChainPose, its messages naming `who`.
Status chainPose(const char* who, const Skeleton& skeleton, const Clip& base, double base_time,
                 Span<const LayerSample> layers, const LayerMask& mask, ReferencePose* pose) {
  if (pose == nullptr) return {StatusCode::kInvalidArgument, strCat(who, ": null pose")};
  for (const LayerSample& l : layers) {
    if (l.clip == nullptr)
      return {StatusCode::kInvalidArgument, strCat(who, ": a layer's clip is null")};
    if (!(l.weight >= 0.0 && l.weight <= 1.0))
      return {StatusCode::kInvalidArgument, strCat(who, ": weight outside [0, 1]")};
  }
  for (uint32_t j : mask.joints)
    if (j >= skeleton.jointCount())
      return {StatusCode::kInvalidArgument, strCat(who, ": a mask joint is past the skeleton")};
  ReferencePose b;
  Status s = evaluatePose(skeleton, base, base_time, &b);
  if (!s.isOk()) return s;
  for (const LayerSample& l : layers) {
    ReferencePose o;
    s = evaluatePose(skeleton, *l.clip, l.time, &o);
    if (!s.isOk()) return s;
    for (uint32_t j : mask.joints) {
      TransformD& t = b.local[j];
      const TransformD& v = o.local[j];
      t.translation = glm::mix(t.translation, v.translation, l.weight);
      t.scale = glm::mix(t.scale, v.scale, l.weight);
      glm::dquat q = v.rotation;
      if (glm::dot(t.rotation, q) < 0.0) q = -q;  // The shorter arc.
      t.rotation = glm::slerp(glm::normalize(t.rotation), glm::normalize(q), l.weight);
    }
  }
  s = composePose(skeleton, b.local, b.model, b.skinning);
  if (!s.isOk()) return s;
  *pose = std::move(b);
  return Status::ok();
}

}  // namespace

Status evaluateLayeredPose(const Skeleton& skeleton, const Clip& base, double base_time,
                           const Clip& overlay, double overlay_time, const LayerMask& mask,
                           double weight, ReferencePose* pose) {
  const LayerSample layer{&overlay, overlay_time, weight};
  return chainPose("evaluateLayeredPose", skeleton, base, base_time,
                   Span<const LayerSample>(&layer, 1), mask, pose);
}

Status evaluateLayeredChainPose(const Skeleton& skeleton, const Clip& base, double base_time,
                                Span<const LayerSample> layers, const LayerMask& mask,
                                ReferencePose* pose) {
  return chainPose("evaluateLayeredChainPose", skeleton, base, base_time, layers, mask, pose);
}

}  // namespace si
