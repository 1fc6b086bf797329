// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// BakedPalette::validate(): a palette from anywhere checked to be as consistent as a bake.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/palette_texel.h"
#include "core/str_cat.h"
#include "si/core/baked_palette.h"
#include "si/core/palette_layout.h"

namespace si {
using detail::strCat;

namespace {

// Relative tolerance of the timing rules: the baker computes interval = duration / intervals in
// double and stores the duration as float.
constexpr double kTimingTolerance = 1e-6;

Status checkClipTiming(const BakedClip& c, const std::string& where) {
  if (c.loop_mode != LoopMode::kOnce && c.loop_mode != LoopMode::kLoop)
    return {StatusCode::kOutOfRange, where + "loop mode must be once or loop"};
  const double duration = c.duration_seconds;
  if (!std::isfinite(duration) || duration < 0.0 || duration > kMaxClipSeconds)
    return {StatusCode::kOutOfRange,
            strCat(where, "duration ", duration, " s is outside [0, ", kMaxClipSeconds, "]")};
  if (c.frame_count == 0 || c.frame_count > kMaxClipFrames)
    return {StatusCode::kOutOfRange,
            strCat(where, c.frame_count, " frames (1 to ", kMaxClipFrames, ")")};
  const double interval = c.frame_interval_seconds;
  if (!std::isfinite(interval) || interval < 0.0)
    return {StatusCode::kOutOfRange, strCat(where, "frame interval ", interval, " s")};
  if (c.frame_count == 1) {
    if (interval != 0.0 || !c.frame_times_seconds.empty())
      return {StatusCode::kOutOfRange,
              where + "a single frame has frame interval 0 and no frame times"};
    return Status::ok();
  }
  // Several frames: the grid divides the duration into a whole number of intervals, no more
  // than the frames allow (STEP keys add frames, never intervals).
  if (!(interval > 0.0) || !(duration > 0.0))
    return {StatusCode::kOutOfRange,
            strCat(where, c.frame_count, " frames need a positive duration and frame interval (",
                   duration, " s, ", interval, " s)")};
  const double intervals = duration / interval;
  const double whole = std::round(intervals);
  if (whole < 1.0 || whole > double(c.frame_count - 1) ||
      std::fabs(intervals - whole) > kTimingTolerance * std::max(1.0, whole))
    return {StatusCode::kOutOfRange,
            strCat(where, "frame interval ", interval, " s does not divide the duration ",
                   duration, " s into at most ", c.frame_count - 1, " whole intervals")};
  const std::vector<double>& times = c.frame_times_seconds;
  if (times.empty()) {
    if (whole != double(c.frame_count - 1))
      return {StatusCode::kOutOfRange,
              strCat(where, c.frame_count, " frames on a uniform grid need ", c.frame_count - 1,
                     " intervals, the duration holds ", whole)};
    return Status::ok();
  }
  if (times.size() != c.frame_count)
    return {StatusCode::kCountMismatch,
            strCat(where, times.size(), " frame times for ", c.frame_count, " frames")};
  const double slack = 2.0 * kTimingTolerance * interval;
  if (!std::isfinite(times[0]) || times[0] < 0.0 || times[0] > slack)
    return {StatusCode::kOutOfRange, strCat(where, "frame time 0 is ", times[0], " s, not 0")};
  for (size_t i = 1; i < times.size(); ++i) {
    const double gap = times[i] - times[i - 1];
    if (!std::isfinite(times[i]) || !(gap >= 0.0) || gap > interval + slack ||
        times[i] > duration)
      return {StatusCode::kOutOfRange,
              strCat(where, "frame time ", i, " (", times[i], " s) is out of order, past the "
                     "duration or more than an interval after the previous one")};
    if (i >= 2 && gap == 0.0 && times[i - 1] == times[i - 2])
      return {StatusCode::kOutOfRange,
              strCat(where, "frame time ", i, " repeats a time a third time")};
  }
  if (times.back() < duration - slack)
    return {StatusCode::kOutOfRange,
            strCat(where, "the last frame time ", times.back(), " s is not the duration ",
                   duration, " s")};
  return Status::ok();
}

// Interpolation: known; a cubic clip has one known mode per interval and a palette with border
// frames; a linear clip has no modes.
Status checkClipInterpolation(const BakedClip& c, uint32_t border_frames,
                              const std::string& where) {
  if (c.interpolation == FrameInterpolation::kLinear) {
    if (!c.interval_modes.empty())
      return {StatusCode::kInvalidArgument, where + "a linear clip has interval modes"};
    return Status::ok();
  }
  if (c.interpolation != FrameInterpolation::kCubic)
    return {StatusCode::kInvalidArgument, where + "unknown frame interpolation"};
  if (border_frames != 1)
    return {StatusCode::kInvalidArgument,
            where + "a cubic clip needs a layout with border frames"};
  if (c.interval_modes.size() != size_t(c.frame_count - 1))
    return {StatusCode::kCountMismatch, strCat(where, c.interval_modes.size(),
                                               " interval modes for ", c.frame_count, " frames")};
  for (size_t i = 0; i < c.interval_modes.size(); ++i)
    if (c.interval_modes[i] > uint8_t(IntervalMode::kCubicEndsNext))
      return {StatusCode::kOutOfRange,
              strCat(where, "interval ", i, " has unknown mode ", int(c.interval_modes[i]))};
  return Status::ok();
}

Status checkClipBounds(const BakedClip& c, const std::string& where) {
  const Aabb& b = c.bounds;
  const Sphere& s = c.bounding_sphere;
  if (!isFinite(glm::vec4(b.min, 0.0f)) || !isFinite(glm::vec4(b.max, 0.0f)) || b.empty())
    return {StatusCode::kOutOfRange, where + "bounds are not finite or empty"};
  if (!isFinite(glm::vec4(s.center, s.radius)) || s.radius < 0.0f ||
      glm::any(glm::lessThan(s.center, b.min)) || glm::any(glm::greaterThan(s.center, b.max)))
    return {StatusCode::kOutOfRange, where + "the bounding sphere is not finite or not in the box"};
  // In double: a box spanning most of the float range has a half diagonal past FLT_MAX squared.
  const double half_diagonal = 0.5 * glm::length(glm::dvec3(b.max) - glm::dvec3(b.min));
  if (double(s.radius) < half_diagonal * (1.0 - 1e-5))
    return {StatusCode::kOutOfRange,
            strCat(where, "the bounding sphere (radius ", s.radius,
                   ") does not contain the box (half diagonal ", half_diagonal, ")")};
  return Status::ok();
}

// Root motion samples: none, or one per frame, finite, starting at the identity, continuous in yaw.
Status checkRootMotion(const BakedClip& c, const std::string& where) {
  if (c.root_motion.empty()) return Status::ok();
  if (c.root_motion.size() != c.frame_count)
    return {StatusCode::kCountMismatch, strCat(where, c.root_motion.size(),
                                               " root motion samples for ", c.frame_count,
                                               " frames")};
  for (size_t f = 0; f < c.root_motion.size(); ++f)
    if (!isFinite(c.root_motion[f]))
      return {StatusCode::kNotFinite, strCat(where, "root motion sample ", f, " is not finite")};
  if (c.root_motion[0] != glm::vec3(0.0f))
    return {StatusCode::kOutOfRange, strCat(where, "root motion sample 0 is not (0, 0, 0)")};
  for (size_t f = 1; f < c.root_motion.size(); ++f)
    if (!(std::fabs(double(c.root_motion[f].z) - double(c.root_motion[f - 1].z)) < 3.14159265358979))
      return {StatusCode::kOutOfRange,
              strCat(where, "root motion yaw jumps by pi or more between frames ", f - 1, " and ",
                     f, " (samples must be unwrapped)")};
  return Status::ok();
}

// Every texel value of every stored joint and morph weight finite; quaternions unit, scales
// positive.
Status checkTexels(const BakedPalette& p) {
  const PaletteLayout& l = p.layout;
  const bool quat = p.format == PaletteFormat::kQuatTranslationF32;
  // Border frames are read too (cubic interpolation): frames -border to count - 1 + border.
  const int64_t border = l.border_frames;
  for (uint32_t c = 0; c < p.clips.size(); ++c)
    for (int64_t f = -border; f < int64_t(p.clips[c].frame_count) + border; ++f) {
      for (uint32_t t = 0; t < l.morph_target_count; t += 4)
        if (!isFinite(detail::paletteTexel(p, l.morphTexel(c, f, t))))
          return {StatusCode::kNotFinite,
                  strCat("palette: clip ", c, " '", p.clips[c].name, "' frame ", f,
                         ": the weights of morph targets ", t, " to ",
                         std::min(t + 4, l.morph_target_count) - 1, " are not finite")};
      for (uint32_t j = 0; j < l.joint_count; ++j) {
        glm::vec4 rows[4] = {};
        for (uint32_t r = 0; r < l.texels_per_joint; ++r) {
          const uint32_t texel = l.frameTexel(c, f) + j * l.joint_stride_texels + r;
          rows[r] = detail::paletteTexel(p, texel);
          if (!isFinite(rows[r]))
            return {StatusCode::kNotFinite,
                    strCat("palette: clip ", c, " '", p.clips[c].name, "' frame ", f, " joint ", j,
                           ": texel ", texel, " is not finite")};
        }
        if (quat && (std::fabs(glm::length(rows[0]) - 1.0f) > 1e-3f || !(rows[1].w > 0.0f)))
          return {StatusCode::kOutOfRange,
                  strCat("palette: clip ", c, " '", p.clips[c].name, "' frame ", f, " joint ", j,
                         ": rotation not unit length or scale not positive")};
      }
    }
  return Status::ok();
}

}  // namespace

Status BakedPalette::validate() const {
  if (format != PaletteFormat::kMatrix3x4F32 && format != PaletteFormat::kMatrix3x4F16 &&
      format != PaletteFormat::kQuatTranslationF32)
    return {StatusCode::kInvalidArgument, "palette: unknown format"};
  // The joint map.
  if (palette_joints.empty() || palette_joints.size() > kMaxPaletteJoints ||
      skeleton_to_palette.size() > 65536 || palette_joints.size() > skeleton_to_palette.size())
    return {StatusCode::kInvalidArgument,
            strCat("palette: ", palette_joints.size(), " palette joints of ",
                   skeleton_to_palette.size(), " skeleton joints")};
  std::vector<int32_t> expected(skeleton_to_palette.size(), -1);
  for (size_t s = 0; s < palette_joints.size(); ++s) {
    const uint32_t j = palette_joints[s];
    if (j >= expected.size() || (s > 0 && j <= palette_joints[s - 1]))
      return {StatusCode::kInvalidArgument,
              strCat("palette: palette joint ", s, " (skeleton joint ", j,
                     ") is out of order or range")};
    expected[j] = int32_t(s);
  }
  if (expected != skeleton_to_palette)
    return {StatusCode::kInvalidArgument,
            "palette: skeleton_to_palette does not map exactly the palette joints to their slots"};
  // The layout follows from the clips' frame counts, the format and the stride.
  if (clips.empty() || clips.size() > kMaxPaletteClips)
    return {StatusCode::kInvalidArgument, strCat("palette: ", clips.size(), " clips (1 to ",
                                                 kMaxPaletteClips, ")")};
  std::vector<uint32_t> frame_counts;
  for (const BakedClip& c : clips) frame_counts.push_back(c.frame_count);
  for (size_t c = 0; c < clips.size(); ++c) {
    Status s = checkClipTiming(clips[c], strCat("palette: clip ", c, " '", clips[c].name, "': "));
    if (s.isOk()) s = checkClipBounds(clips[c], strCat("palette: clip ", c, " '", clips[c].name, "': "));
    if (s.isOk())
      s = checkClipInterpolation(clips[c], layout.border_frames,
                                 strCat("palette: clip ", c, " '", clips[c].name, "': "));
    if (s.isOk())
      s = validateMarkers(clips[c].markers, clips[c].duration_seconds,
                          strCat("palette: clip ", c, " '", clips[c].name, "': "));
    if (s.isOk()) s = checkRootMotion(clips[c], strCat("palette: clip ", c, " '", clips[c].name, "': "));
    if (!s.isOk()) return s;
  }
  if (layout.texels_per_joint != texelsPerJoint(format) || layout.joint_stride_texels > 64 ||
      layout.joint_count != palette_joints.size())
    return {StatusCode::kInvalidArgument,
            "palette: the layout's joint count or texels per joint do not match the palette"};
  PaletteLayoutDesc ld;
  ld.joint_count = layout.joint_count;
  ld.clip_frame_counts = frame_counts;
  ld.texels_per_joint = layout.texels_per_joint;
  ld.joint_stride_texels = layout.joint_stride_texels;
  ld.max_texture_size = 32768;
  ld.border_frames = layout.border_frames;
  ld.morph_target_count = layout.morph_target_count;
  PaletteLayout derived;
  Status s = computePaletteLayout(ld, &derived);
  if (!s.isOk()) return {StatusCode::kInvalidArgument, "palette: " + s.message()};
  if (derived.width != layout.width || derived.width_log2 != layout.width_log2 ||
      derived.height != layout.height ||
      derived.frame_stride_texels != layout.frame_stride_texels ||
      derived.clip_first_texel != layout.clip_first_texel ||
      derived.border_frames != layout.border_frames ||
      derived.clip_frame_count != layout.clip_frame_count ||
      derived.morph_first_texel != layout.morph_first_texel)
    return {StatusCode::kInvalidArgument,
            strCat("palette: the layout (", layout.width, "x", layout.height,
                   ") is not the one its clips need (", derived.width, "x", derived.height, ")")};
  for (size_t c = 0; c < clips.size(); ++c)
    if (clips[c].first_texel != layout.clip_first_texel[c])
      return {StatusCode::kInvalidArgument,
              strCat("palette: clip ", c, " first texel ", clips[c].first_texel,
                     " is not the layout's ", layout.clip_first_texel[c])};
  if (texel_bytes.size() != layout.textureTexelCount() * bytesPerTexel(format))
    return {StatusCode::kCountMismatch,
            strCat("palette: ", texel_bytes.size(), " texel bytes, the layout needs ",
                   layout.textureTexelCount() * bytesPerTexel(format))};
  if (!std::isfinite(character_height) || character_height < 0.0f)
    return {StatusCode::kOutOfRange, "palette: character height is not finite and >= 0"};
  if (!joint_bounds.empty() && joint_bounds.size() != palette_joints.size())
    return {StatusCode::kCountMismatch,
            strCat("palette: ", joint_bounds.size(), " joint bounds for ", palette_joints.size(),
                   " palette joints")};
  for (size_t j = 0; j < joint_bounds.size(); ++j) {
    const Aabb& b = joint_bounds[j];
    const bool none = b.min == Aabb().min && b.max == Aabb().max;  // No drawn vertex.
    if (!isFinite(glm::vec4(b.min, 0.0f)) || !isFinite(glm::vec4(b.max, 0.0f)) ||
        (b.empty() && !none))
      return {StatusCode::kOutOfRange,
              strCat("palette: the bounds of palette joint ", j,
                     " are not finite, or inverted on an axis (min > max)")};
  }
  return checkTexels(*this);
}

}  // namespace si
