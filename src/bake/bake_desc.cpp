// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/bake/bake_desc.h"

#include <cmath>

#include "core/str_cat.h"

namespace si {
using detail::strCat;

PaletteFormat resolvePaletteFormat(PaletteFormat f) {
  return f == PaletteFormat::kDefault ? PaletteFormat::kMatrix3x4F32 : f;
}

const char* paletteFormatName(PaletteFormat f) {
  switch (f) {
    case PaletteFormat::kDefault: return "default";
    case PaletteFormat::kMatrix3x4F32: return "matrix3x4_f32";
    case PaletteFormat::kMatrix3x4F16: return "matrix3x4_f16";
    case PaletteFormat::kQuatTranslationF32: return "quat_translation_f32";
  }
  return "invalid";
}

uint32_t texelsPerJoint(PaletteFormat f) {
  return resolvePaletteFormat(f) == PaletteFormat::kQuatTranslationF32 ? 2u : 3u;
}

uint32_t bytesPerTexel(PaletteFormat f) {
  return resolvePaletteFormat(f) == PaletteFormat::kMatrix3x4F16 ? 8u : 16u;
}

BakeDesc resolveDefaults(const BakeDesc& desc) {
  BakeDesc d = desc;
  d.format = resolvePaletteFormat(d.format);
  if (d.sample_rate_hz == 0.0f) d.sample_rate_hz = 30.0f;
  if (d.joint_stride_texels == 0) d.joint_stride_texels = texelsPerJoint(d.format) == 3 ? 4 : 2;
  if (d.max_texture_size == 0) d.max_texture_size = 16384;
  return d;
}

FramePlan planFrames(double duration_seconds, double rate_hz, LoopMode loop_mode) {
  FramePlan p;
  if (!(duration_seconds > 0.0) || !(rate_hz > 0.0)) return p;
  // A tiny epsilon keeps 1.0 s at 30 Hz at 30 intervals despite rounding in duration * rate.
  const double intervals = std::max(1.0, std::ceil(duration_seconds * rate_hz - 1e-9));
  if (resolveLoopMode(loop_mode) == LoopMode::kLoop) {
    p.frame_count = static_cast<uint32_t>(std::min(intervals, 4294967295.0));
  } else {
    p.frame_count = static_cast<uint32_t>(std::min(intervals + 1.0, 4294967295.0));
  }
  p.frame_interval_seconds = duration_seconds / intervals;
  return p;
}

Status planPalette(const Character& character, const BakeDesc& in_desc, PalettePlan* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "planPalette: out is null"};
  const BakeDesc d = resolveDefaults(in_desc);
  if (!std::isfinite(d.sample_rate_hz) || d.sample_rate_hz <= 0.0f)
    return {StatusCode::kInvalidArgument, "BakeDesc.sample_rate_hz must be finite and positive"};
  if (d.format != PaletteFormat::kMatrix3x4F32 && d.format != PaletteFormat::kMatrix3x4F16 &&
      d.format != PaletteFormat::kQuatTranslationF32)
    return {StatusCode::kInvalidArgument, "BakeDesc.format is not a known PaletteFormat"};

  PalettePlan plan;
  if (d.clip_names.empty()) {
    for (size_t c = 0; c < character.clips.size(); ++c)
      plan.clip_indices.push_back(static_cast<uint32_t>(c));
  } else {
    for (const std::string& name : d.clip_names) {
      const int32_t c = character.findClip(name);
      if (c < 0) return {StatusCode::kNotFound, strCat("bake: no clip named '", name, "'")};
      plan.clip_indices.push_back(static_cast<uint32_t>(c));
    }
  }
  if (plan.clip_indices.empty())
    return {StatusCode::kInvalidArgument, "bake: the character has no clips to bake"};
  std::vector<uint32_t> frame_counts;
  for (uint32_t c : plan.clip_indices) {
    const Clip& clip = character.clips[c];
    const FramePlan f = planFrames(clip.duration_seconds, d.sample_rate_hz, clip.loop_mode);
    if (f.frame_count > (1u << 20))
      return {StatusCode::kLimitExceeded, strCat("bake: clip '", clip.name, "' would need ",
                                                 f.frame_count, " frames (at most 2^20)")};
    plan.frames.push_back(f);
    frame_counts.push_back(f.frame_count);
  }
  PaletteLayoutDesc ld;
  ld.joint_count = static_cast<uint32_t>(character.skeleton.jointCount());
  ld.clip_frame_counts = frame_counts;
  ld.texels_per_joint = texelsPerJoint(d.format);
  ld.joint_stride_texels = d.joint_stride_texels;
  ld.max_texture_size = d.max_texture_size;
  Status s = computePaletteLayout(ld, &plan.layout);
  if (!s.isOk()) return s;
  plan.texture_bytes = plan.layout.textureTexelCount() * bytesPerTexel(d.format);
  *out = std::move(plan);
  return Status::ok();
}

}  // namespace si
