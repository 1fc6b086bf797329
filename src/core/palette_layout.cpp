// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/palette_layout.h"

#include <algorithm>
#include <cassert>

#include "core/str_cat.h"
#include "si/core/morph_target.h"

namespace si {
using detail::strCat;

namespace {
bool isPowerOfTwo(uint64_t v) { return v != 0 && (v & (v - 1)) == 0; }
uint32_t log2u(uint64_t v) {
  uint32_t l = 0;
  while ((uint64_t(1) << l) < v) ++l;
  return l;
}
}  // namespace

PaletteLayoutDesc resolveDefaults(const PaletteLayoutDesc& desc) {
  PaletteLayoutDesc d = desc;
  if (d.joint_stride_texels == 0 && d.texels_per_joint > 0)
    d.joint_stride_texels = uint32_t(1) << log2u(d.texels_per_joint);
  if (d.max_texture_size == 0) d.max_texture_size = 16384;
  return d;
}

uint32_t PaletteLayout::frameTexel(uint32_t clip, int64_t frame) const {
  assert(clip < clip_first_texel.size() && frame >= -int64_t(border_frames) &&
         frame < int64_t(clip_frame_count[clip]) + border_frames);
  return uint32_t(int64_t(clip_first_texel[clip]) + frame * int64_t(frame_stride_texels));
}

uint32_t PaletteLayout::texelIndex(uint32_t clip, uint32_t frame, uint32_t joint,
                                   uint32_t row) const {
  assert(clip < clip_first_texel.size() && frame < clip_frame_count[clip] &&
         joint < joint_count && row < texels_per_joint);
  return clip_first_texel[clip] + frame * frame_stride_texels + joint * joint_stride_texels + row;
}

Status computePaletteLayout(const PaletteLayoutDesc& in_desc, PaletteLayout* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "computePaletteLayout: out is null"};
  const PaletteLayoutDesc d = resolveDefaults(in_desc);
  if (d.joint_count == 0)
    return {StatusCode::kInvalidArgument, "PaletteLayoutDesc.joint_count must be at least 1"};
  if (d.clip_frame_counts.empty())
    return {StatusCode::kInvalidArgument, "PaletteLayoutDesc.clip_frame_counts is empty"};
  if (d.texels_per_joint < 1 || d.texels_per_joint > 4)
    return {StatusCode::kInvalidArgument, "PaletteLayoutDesc.texels_per_joint must be 1 to 4"};
  if (d.joint_stride_texels < d.texels_per_joint)
    return {StatusCode::kInvalidArgument,
            "PaletteLayoutDesc.joint_stride_texels must be at least texels_per_joint"};
  if (d.border_frames > 1)
    return {StatusCode::kInvalidArgument, "PaletteLayoutDesc.border_frames must be 0 or 1"};
  if (!isPowerOfTwo(d.max_texture_size))
    return {StatusCode::kInvalidArgument,
            "PaletteLayoutDesc.max_texture_size must be a power of two"};
  if (d.morph_target_count > kMaxMorphTargets)
    return {StatusCode::kInvalidArgument,
            strCat("PaletteLayoutDesc.morph_target_count must be at most ", kMaxMorphTargets)};

  PaletteLayout layout;
  layout.joint_count = d.joint_count;
  layout.texels_per_joint = d.texels_per_joint;
  layout.joint_stride_texels = d.joint_stride_texels;
  layout.border_frames = d.border_frames;
  layout.morph_target_count = d.morph_target_count;
  const uint64_t joints = uint64_t(d.joint_count) * d.joint_stride_texels;
  const uint64_t morph_texels = (d.morph_target_count + 3u) / 4u;
  const uint64_t frame_stride = joints + (morph_texels + d.joint_stride_texels - 1) /
                                             d.joint_stride_texels * d.joint_stride_texels;
  if (joints > 0xFFFFFFFFull)
    return {StatusCode::kLimitExceeded,
            strCat("palette: needs more than 2^32 texels (", d.joint_count, " joints)")};
  layout.morph_first_texel = uint32_t(joints);
  uint64_t total = 0;
  for (size_t c = 0; c < d.clip_frame_counts.size(); ++c) {
    const uint32_t frames = d.clip_frame_counts[c];
    if (frames == 0)
      return {StatusCode::kInvalidArgument, strCat("PaletteLayoutDesc: clip ", c, " has 0 frames")};
    total += frame_stride * d.border_frames;
    layout.clip_first_texel.push_back(static_cast<uint32_t>(std::min<uint64_t>(total, 0xFFFFFFFFull)));
    layout.clip_frame_count.push_back(frames);
    total += frame_stride * (uint64_t(frames) + d.border_frames);
    if (total > 0xFFFFFFFFull)
      return {StatusCode::kLimitExceeded,
              strCat("palette: needs more than 2^32 texels (", d.joint_count, " joints)")};
  }
  const uint64_t max = d.max_texture_size;
  if (total > max * max)
    return {StatusCode::kLimitExceeded,
            strCat("palette: ", total, " texels (", d.joint_count, " joints, ", frame_stride,
                   " texels per frame) do not fit in a ", max, "x", max, " texture")};
  // Smallest power-of-two width whose height stays within the width (near square), at least
  // one joint stride wide so joints never straddle rows when the stride is a power of two.
  uint64_t width = uint64_t(1) << ((log2u(total) + 1) / 2);
  if (width < d.joint_stride_texels) width = uint64_t(1) << log2u(d.joint_stride_texels);
  if (width > max) width = max;
  const uint64_t height = (total + width - 1) / width;
  assert(height <= max && "checked against max * max above");
  layout.frame_stride_texels = static_cast<uint32_t>(frame_stride);
  layout.width = static_cast<uint32_t>(width);
  layout.width_log2 = log2u(width);
  layout.height = static_cast<uint32_t>(height);
  layout.used_texel_count = total;
  *out = std::move(layout);
  return Status::ok();
}

}  // namespace si
