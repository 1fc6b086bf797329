// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Layered animation's error: the shader's matrix blend from the palette against the local-space
// reference.
#include "si/bake/layer_error.h"

#include <algorithm>

#include "bake/clip_measurement.h"
#include "core/str_cat.h"
#include "si/core/reference_evaluator.h"

namespace si {

using detail::strCat;

namespace {

// The skinning matrix of every skeleton joint the shader uses for `base` layered with
// `overlay` through `mask` at `weight` (identity for joints the palette does not store).
void emulateLayered(const BakedPalette& palette, const LayerMask& mask, uint32_t base,
                    const FrameSample& sb, uint32_t overlay, const FrameSample& so, float weight,
                    std::vector<glm::mat4>* out) {
  const size_t slots = palette.palette_joints.size();
  std::vector<glm::mat4> b(slots), o(slots);
  for (uint32_t s = 0; s < slots; ++s) {
    b[s] = emulateSkinningMatrix(palette, base, sb, s);
    o[s] = emulateSkinningMatrix(palette, overlay, so, s);
  }
  out->assign(palette.skeleton_to_palette.size(), glm::mat4(1.0f));
  for (size_t j = 0; j < out->size(); ++j) {
    const int32_t s = palette.skeleton_to_palette[j];
    if (s < 0) continue;
    (*out)[j] = emulateLayeredMatrix(mask, uint32_t(s), weight,
                                     [&](uint32_t at) { return b[at]; },
                                     [&](uint32_t at) { return o[at]; });
  }
}

}  // namespace

Status measureLayeredError(const Character& character, const BakedPalette& palette,
                           const LayerMask& mask, uint32_t base_clip, uint32_t overlay_clip,
                           const std::vector<float>& weights_in, LayeredErrorReport* report,
                           uint32_t samples) {
  if (report == nullptr)
    return {StatusCode::kInvalidArgument, "measureLayeredError: null report"};
  if (base_clip >= palette.clips.size() || overlay_clip >= palette.clips.size())
    return {StatusCode::kInvalidArgument,
            strCat("measureLayeredError: clip ", std::max(base_clip, overlay_clip),
                   " is past the palette's ", palette.clips.size())};
  if (palette.skeleton_to_palette.size() != character.skeleton.jointCount())
    return {StatusCode::kInvalidArgument,
            "measureLayeredError: the palette was not baked from this character's skeleton"};
  Status s = mask.validate(palette);
  if (!s.isOk()) return {s.code(), "measureLayeredError: " + s.message()};
  const std::vector<float> weights =
      weights_in.empty() ? std::vector<float>{0.25f, 0.5f, 0.75f, 1.0f} : weights_in;
  for (float w : weights)
    if (!(w >= 0.0f && w <= 1.0f))
      return {StatusCode::kInvalidArgument, "measureLayeredError: a weight is outside [0, 1]"};
  const int32_t cb = character.findClip(palette.clips[base_clip].name);
  const int32_t co = character.findClip(palette.clips[overlay_clip].name);
  if (cb < 0 || co < 0)
    return {StatusCode::kNotFound,
            strCat("measureLayeredError: the character has no clip '",
                   palette.clips[cb < 0 ? base_clip : overlay_clip].name, "'")};
  const Clip& base = character.clips[size_t(cb)];
  const Clip& overlay = character.clips[size_t(co)];
  // The shader reads the vertex format's quantized weights.
  const SkinnedMesh mesh = detail::storedWeightsMesh(character.mesh);
  const size_t n = mesh.positions.size();
  std::vector<glm::vec3> emulated(n);
  std::vector<glm::dvec3> reference(n);
  std::vector<glm::mat4> matrices;
  ReferencePose pose;
  const double height = std::max(1e-30, double(character.height()));
  const uint32_t count = samples == 0 ? 64 : samples;
  const double span = std::max(base.duration_seconds, overlay.duration_seconds);
  LayeredErrorReport r;
  r.samples = count;
  for (float w : weights) {
    LayeredErrorReport::AtWeight at;
    at.weight = w;
    for (uint32_t k = 0; k < count; ++k) {
      const double t = span * (k + 0.37) / count;  // Off the frame grid.
      const FrameSample sb = sampleFrames(palette.clips[base_clip], clipLocalTime(base, t));
      const FrameSample so = sampleFrames(palette.clips[overlay_clip], clipLocalTime(overlay, t));
      emulateLayered(palette, mask, base_clip, sb, overlay_clip, so, w, &matrices);
      s = emulateSkinning(mesh, matrices, emulated, {});
      if (s.isOk()) s = evaluateLayeredPose(character.skeleton, base, t, overlay, t, mask, w, &pose);
      if (s.isOk()) s = skinVertices(character.mesh, pose.skinning, reference, {}, {});
      if (!s.isOk()) return s;
      for (size_t v = 0; v < n; ++v) {
        const double e = glm::length(glm::dvec3(emulated[v]) - reference[v]);
        at.max_error_units = std::max(at.max_error_units, e);
        if (e > r.max_error_units) {
          r.max_error_units = e;
          r.worst_weight = w;
          r.worst_time_seconds = t;
        }
      }
    }
    at.max_error_ratio = at.max_error_units / height;
    r.per_weight.push_back(at);
  }
  r.max_error_ratio = r.max_error_units / height;
  *report = std::move(r);
  return Status::ok();
}

}  // namespace si
