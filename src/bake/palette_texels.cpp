// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The baker's texel writer. Technique: B. Dudash, "Skinned Instancing", NVIDIA whitepaper
// (2007), and GPU Gems 3 ch. 2.
#include "bake/palette_texels.h"

#include <cmath>

#include "bake/border_frames.h"
#include "core/palette_texel.h"
#include "core/str_cat.h"
#include "core/validated_evaluation.h"
#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"

namespace si::detail {

namespace {

// A skinning matrix as rotation, translation and uniform scale, when it is one.
struct Rigid {
  glm::dquat rotation;
  glm::dvec3 translation;
  double scale = 1.0;
};

// Relative tolerance for "uniform and orthogonal" when checking a joint for the rigid format.
constexpr double kRigidTolerance = 1e-4;

bool decomposeRigid(const glm::dmat4& m, Rigid* out) {
  const glm::dvec3 c0(m[0]), c1(m[1]), c2(m[2]);
  const double s0 = glm::length(c0), s1 = glm::length(c1), s2 = glm::length(c2);
  const double s = (s0 + s1 + s2) / 3.0;
  out->translation = glm::dvec3(m[3]);
  if (s < 1e-12) {  // Zero scale: representable, rotation irrelevant.
    out->rotation = glm::dquat(1, 0, 0, 0);
    out->scale = 0.0;
    return true;
  }
  const double tol = kRigidTolerance * s;
  if (std::fabs(s0 - s) > tol || std::fabs(s1 - s) > tol || std::fabs(s2 - s) > tol) return false;
  if (std::fabs(glm::dot(c0, c1)) > tol * s || std::fabs(glm::dot(c1, c2)) > tol * s ||
      std::fabs(glm::dot(c0, c2)) > tol * s)
    return false;
  if (glm::dot(glm::cross(c0, c1), c2) <= 0.0) return false;  // Mirrored.
  glm::dquat q = glm::quat_cast(glm::dmat3(c0 / s, c1 / s, c2 / s));
  q = safeNormalize(q);
  if (q.w < 0.0) q = -q;
  out->rotation = q;
  out->scale = s;
  return true;
}

void storeTexel(BakedPalette* p, uint32_t index, const glm::dvec4& v) {
  detail::storeFormatTexel(p->format, p->texel_bytes.data(), index, glm::vec4(v));
}

// The first entry of skinning matrix `m`'s stored rows that is not finite or past `range`
// (a NaN compares false), or 0 when every one fits.
double outOfRangeEntry(const glm::dmat4& m, double range) {
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 3; ++row)
      if (!(std::fabs(m[col][row]) <= range)) return m[col][row];
  return 0.0;
}

}  // namespace

Status bakeTexels(const Character& character, const BakeDesc& d, const PalettePlan& plan,
                  BakedPalette* out) {
  BakedPalette p;
  p.format = d.format;
  p.layout = plan.layout;
  p.palette_joints = plan.palette_joints;
  p.skeleton_to_palette.assign(character.skeleton.jointCount(), -1);
  for (size_t s = 0; s < p.palette_joints.size(); ++s)
    p.skeleton_to_palette[p.palette_joints[s]] = static_cast<int32_t>(s);
  p.texel_bytes.assign(size_t(p.layout.textureTexelCount()) * bytesPerTexel(d.format), 0);
  p.character_height = character.height();

  ReferencePose pose;
  GroundMotion motion;
  const uint32_t targets = p.layout.morph_target_count;
  std::vector<double> weights(targets);
  for (size_t c = 0; c < plan.clip_indices.size(); ++c) {
    const Clip& clip = character.clips[plan.clip_indices[c]];
    BakedClip bc;
    bc.name = clip.name;
    bc.loop_mode = resolveLoopMode(clip.loop_mode);
    bc.markers = clip.markers;
    bc.duration_seconds = clip.duration_seconds;
    bc.frame_count = plan.frames[c].frame_count;
    bc.frame_interval_seconds = plan.frames[c].frame_interval_seconds;
    bc.first_texel = p.layout.clip_first_texel[c];
    bc.frame_times_seconds = plan.frames[c].frame_times_seconds;
    const std::vector<uint8_t>& before_step = plan.frames[c].before_step;
    for (uint32_t f = 0; f < bc.frame_count; ++f) {
      // The last frame lies exactly on the clip's end; a frame before a STEP key holds the
      // pose an instant before it (the largest double below the key time).
      double t = f + 1 == bc.frame_count && f > 0 ? double(clip.duration_seconds)
                                                  : f * bc.frame_interval_seconds;
      if (!bc.frame_times_seconds.empty()) {
        t = bc.frame_times_seconds[f];
        if (before_step[f]) t = std::nextafter(t, 0.0);
      }
      Status s = evaluateValidatedLocalPose(character.skeleton, clip, t, &pose);
      if (s.isOk() && clip.root_motion.extract)
        s = evaluateValidatedRootMotion(character.skeleton, clip, t, &motion);
      if (!s.isOk()) return s;
      if (clip.root_motion.extract) {  // Yaw unwrapped from the previous frame's.
        const double previous = f == 0 ? 0.0 : double(bc.root_motion.back().z);
        const double yaw = f == 0 ? 0.0 : previous + wrapAngle(motion.yaw - previous);
        bc.root_motion.push_back(f == 0 ? glm::vec3(0.0f)
                                        : glm::vec3(glm::dvec3(motion.translation, yaw)));
      }
      for (uint32_t slot = 0; slot < p.palette_joints.size(); ++slot) {
        const uint32_t joint = p.palette_joints[slot];
        const glm::dmat4& m = pose.skinning[joint];
        // Never a non-finite texel: a pose the format cannot hold is refused by name.
        const double bad = outOfRangeEntry(m, formatRange(d.format));
        if (bad != 0.0)
          return {StatusCode::kOutOfRange,
                  strCat("bake: clip '", clip.name, "' frame ", f, " (t=", t, " s), joint ", joint,
                         " '", character.skeleton.joint_names[joint],
                         "': its skinning matrix holds ", bad, ", past what ",
                         paletteFormatName(d.format), " stores (", formatRange(d.format),
                         "): the file's transforms compose beyond the palette's range")};
        if (d.format == PaletteFormat::kQuatTranslationF32) {
          Rigid r;
          if (!decomposeRigid(m, &r))
            return {StatusCode::kUnsupported,
                    strCat("bake: clip '", clip.name, "': joint ", joint, " '",
                           character.skeleton.joint_names[joint], "' has non-uniform or negative "
                           "scale at t=", t, " s; quat_translation_f32 cannot represent it (use "
                           "a matrix format)")};
          storeTexel(&p, p.layout.texelIndex(uint32_t(c), f, slot, 0),
                     glm::dvec4(r.rotation.x, r.rotation.y, r.rotation.z, r.rotation.w));
          storeTexel(&p, p.layout.texelIndex(uint32_t(c), f, slot, 1),
                     glm::dvec4(r.translation, r.scale));
        } else {
          for (uint32_t row = 0; row < 3; ++row)
            storeTexel(&p, p.layout.texelIndex(uint32_t(c), f, slot, row),
                       glm::dvec4(m[0][row], m[1][row], m[2][row], m[3][row]));
        }
      }
      // The morph targets' weights at the frame's time, four to a texel after the joints.
      if (targets == 0) continue;
      evaluateValidatedMorphWeights(character.mesh, clip, t, weights);
      for (uint32_t k = 0; k < targets; ++k)
        if (!(std::fabs(weights[k]) <= formatRange(d.format)))
          return {StatusCode::kOutOfRange,
                  strCat("bake: clip '", clip.name, "' frame ", f, " (t=", t, " s): morph target ",
                         k, " has weight ", weights[k], ", past what ", paletteFormatName(d.format),
                         " stores (", formatRange(d.format), ")")};
      for (uint32_t k = 0; k < targets; k += 4) {
        glm::dvec4 w4(0.0);
        for (uint32_t i = 0; i < 4 && k + i < targets; ++i) w4[int(i)] = weights[k + i];
        storeTexel(&p, p.layout.morphTexel(uint32_t(c), f, k), w4);
      }
    }
    p.clips.push_back(std::move(bc));
    detail::finishClipFrames(&p, uint32_t(c), plan.interpolations[c], plan.frames[c].breaks);
  }
  *out = std::move(p);
  return Status::ok();
}


}  // namespace si::detail
