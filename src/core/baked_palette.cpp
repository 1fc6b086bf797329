// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Palette formats, IEEE half conversion (round to nearest even, as GPUs store RGBA16F), and the
// CPU emulation of the vertex shader's palette reads: the same texel addressing, decoding, frame
// interpolation and skinning, in float.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/frame_times_sample.h"
#include "core/palette_texel.h"
#include "core/skinned_normal.h"
#include "core/str_cat.h"
#include "si/core/baked_palette.h"

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

const char* frameInterpolationName(FrameInterpolation i) {
  switch (i) {
    case FrameInterpolation::kLinear: return "linear";
    case FrameInterpolation::kCubic: return "cubic";
  }
  return "invalid";
}

float unpackFraction(uint32_t word, IntervalMode* mode) {
  if (mode != nullptr) *mode = static_cast<IntervalMode>(word >> 30);
  word &= 0x3FFFFFFFu;
  float f;
  std::memcpy(&f, &word, 4);
  return f;
}

uint32_t texelsPerJoint(PaletteFormat f) {
  return resolvePaletteFormat(f) == PaletteFormat::kQuatTranslationF32 ? 2u : 3u;
}

uint32_t bytesPerTexel(PaletteFormat f) {
  return resolvePaletteFormat(f) == PaletteFormat::kMatrix3x4F16 ? 8u : 16u;
}

uint16_t floatToHalf(float value) {
  uint32_t x;
  std::memcpy(&x, &value, 4);
  const uint32_t sign = (x >> 16) & 0x8000u;
  const uint32_t exponent = (x >> 23) & 0xFFu;
  uint32_t mantissa = x & 0x7FFFFFu;
  if (exponent == 0xFFu) return uint16_t(sign | 0x7C00u | (mantissa ? 0x200u : 0u));
  const int e = int(exponent) - 127 + 15;
  if (e >= 31) return uint16_t(sign | 0x7C00u);
  if (e <= 0) {  // Half subnormal (or zero): value = m * 2^-24.
    if (e < -10) return uint16_t(sign);
    mantissa |= 0x800000u;
    const uint32_t shift = uint32_t(14 - e);
    uint32_t m = mantissa >> shift;
    const uint32_t rest = mantissa & ((1u << shift) - 1u), halfway = 1u << (shift - 1u);
    if (rest > halfway || (rest == halfway && (m & 1u))) ++m;
    return uint16_t(sign | m);
  }
  uint32_t h = sign | (uint32_t(e) << 10) | (mantissa >> 13);
  const uint32_t rest = mantissa & 0x1FFFu;
  if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;  // A carry rounds up the exponent.
  return uint16_t(h);
}

float halfToFloat(uint16_t h) {
  const uint32_t sign = uint32_t(h & 0x8000u) << 16;
  const uint32_t exponent = (h >> 10) & 0x1Fu;
  const uint32_t mantissa = h & 0x3FFu;
  uint32_t bits;
  if (exponent == 0) {
    const float magnitude = std::ldexp(float(mantissa), -24);
    return sign ? -magnitude : magnitude;
  }
  if (exponent == 31) {
    bits = sign | 0x7F800000u | (mantissa << 13);
  } else {
    bits = sign | ((exponent - 15 + 127) << 23) | (mantissa << 13);
  }
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}


int32_t BakedPalette::findClip(const std::string& clip_name) const {
  for (size_t i = 0; i < clips.size(); ++i)
    if (clips[i].name == clip_name) return static_cast<int32_t>(i);
  return -1;
}

FrameSample sampleFrames(const BakedClip& clip, double local_time_seconds) {
  return sampleFrames(clip, local_time_seconds, {});
}

std::vector<uint32_t> frameSearchStarts(const BakedClip& clip) {
  std::vector<uint32_t> starts;
  const std::vector<double>& times = clip.frame_times_seconds;
  const double interval = clip.frame_interval_seconds;
  if (clip.frame_count < 2 || times.size() != clip.frame_count || !(interval > 0.0)) return starts;
  starts.resize(clip.frame_count - 1);
  for (uint32_t i = 0; i < starts.size(); ++i) {
    // Any t of interval i has t / interval >= i, so t > (i - 1/2) * interval.
    const double below = std::max(0.0, (double(i) - 0.5) * interval);
    const size_t u = size_t(std::upper_bound(times.begin(), times.end(), below) - times.begin());
    starts[i] = uint32_t(std::max<size_t>(i, u));
  }
  return starts;
}

FrameSample sampleFrames(const BakedClip& clip, double local_time_seconds,
                         Span<const uint32_t> search_starts) {
  FrameSample s;
  const uint32_t n = clip.frame_count;
  if (n <= 1 || !(clip.frame_interval_seconds > 0.0)) return s;
  // NaN times play the start; t in [0, duration].
  const double t = local_time_seconds > 0.0
                       ? std::min(local_time_seconds, double(clip.duration_seconds)) : 0.0;
  const double position = t / clip.frame_interval_seconds;
  const uint32_t last_interval = n - 2;
  // Compared in double before the conversion, so that no duration or interval (a palette that
  // BakedPalette::validate() would refuse included) converts an out-of-range value.
  uint32_t i = position >= double(last_interval) ? last_interval
               : position > 0.0                  ? static_cast<uint32_t>(position)
                                                 : 0u;
  // Uniform grid: constant time (also for frame times that do not match the frame count,
  // which validate() refuses).
  if (clip.frame_times_seconds.size() != n) {
    s.frame = i;
    s.next_frame = i + 1;
    s.fraction = static_cast<float>(std::min(std::max(position - double(i), 0.0), 1.0));
    s.mode = intervalModeAt(clip, i);
    return s;
  }
  // STEP keys add frames, never remove grid frames before t, so the last frame at or before t
  // is at index >= the grid index: search from there.
  const auto& times = clip.frame_times_seconds;
  size_t k;
  if (search_starts.size() == size_t(last_interval) + 1) {
    k = std::max<size_t>(i, search_starts[i]);
    while (k < times.size() && times[k] <= t) ++k;
  } else {
    const auto first = times.begin() + std::ptrdiff_t(std::min<size_t>(i, times.size()));
    k = size_t(std::upper_bound(first, times.end(), t) - times.begin());
  }
  return detail::frameTimesSample(clip, t, k);
}

std::vector<uint8_t> cubicIntervalModes(const BakedClip& clip, bool wraps,
                                        Span<const uint8_t> breaks) {
  const uint32_t n = clip.frame_count;
  std::vector<uint8_t> modes(n > 1 ? n - 1 : 0, uint8_t(IntervalMode::kLinear));
  const std::vector<double>& times = clip.frame_times_seconds;
  const double dt = clip.frame_interval_seconds;
  const auto span = [&](uint32_t i) { return times.size() == n ? times[i + 1] - times[i] : dt; };
  const auto broken = [&](uint32_t f) { return breaks.size() == n && breaks[f] != 0; };
  const auto even = [&](double a, double b) { return std::fabs(a - b) <= 0.01 * std::max(a, b); };
  for (uint32_t i = 0; i + 1 < n; ++i) {
    const double here = span(i);
    if (!(here > 0.0)) continue;  // A STEP key's zero-length span: linear, fraction 1.
    // The tangent at frame i may use frame i - 1: the curve is smooth through frame i.
    const bool left = !broken(i) && (i > 0 ? even(span(i - 1), here) : wraps);
    const bool right = !broken(i + 1) && (i + 2 < n ? even(span(i + 1), here) : wraps);
    const IntervalMode m = left && right ? IntervalMode::kCubic
                           : right       ? IntervalMode::kCubicStartsHere
                           : left        ? IntervalMode::kCubicEndsNext
                                         : IntervalMode::kLinear;
    // Extrapolating needs the third frame on the smooth side to be evenly spaced too.
    if ((m == IntervalMode::kCubicStartsHere && (i + 2 >= n || !even(span(i + 1), here))) ||
        (m == IntervalMode::kCubicEndsNext && (i == 0 || !even(span(i - 1), here))))
      continue;
    modes[i] = uint8_t(m);
  }
  return modes;
}

namespace {

glm::vec4 readTexel(const BakedPalette& p, uint32_t index) {
  return detail::paletteTexel(p, index);
}

glm::mat4 fromRows(const glm::vec4& r0, const glm::vec4& r1, const glm::vec4& r2) {
  glm::mat4 m(1.0f);
  for (int c = 0; c < 4; ++c) {
    m[c][0] = r0[c];
    m[c][1] = r1[c];
    m[c][2] = r2[c];
  }
  return m;
}

glm::mat4 fromRigid(const glm::vec4& q, const glm::vec4& ts) {
  const glm::mat3 r = glm::mat3_cast(glm::quat(q.w, q.x, q.y, q.z));
  glm::mat4 m(1.0f);
  for (int c = 0; c < 3; ++c) m[c] = glm::vec4(r[c] * ts.w, 0.0f);
  m[3] = glm::vec4(glm::vec3(ts), 1.0f);
  return m;
}

}  // namespace

glm::mat4 decodeJoint(const BakedPalette& p, uint32_t clip, uint32_t frame, uint32_t slot) {
  const PaletteLayout& l = p.layout;
  if (p.format == PaletteFormat::kQuatTranslationF32)
    return fromRigid(readTexel(p, l.texelIndex(clip, frame, slot, 0)),
                     readTexel(p, l.texelIndex(clip, frame, slot, 1)));
  return fromRows(readTexel(p, l.texelIndex(clip, frame, slot, 0)),
                  readTexel(p, l.texelIndex(clip, frame, slot, 1)),
                  readTexel(p, l.texelIndex(clip, frame, slot, 2)));
}

namespace {

// Catmull-Rom weights of frames i - 1, i, i + 1, i + 2 at fraction u, with an extrapolated end
// folded in: frame i - 1 = 3 f(i) - 3 f(i + 1) + f(i + 2), or frame i + 2 = 3 f(i + 1) - 3 f(i)
// + f(i - 1). At u = 0 and 1 the weights are exactly (0 1 0 0) and (0 0 1 0).
glm::vec4 cubicWeights(float u, IntervalMode mode) {
  const float u2 = u * u, u3 = u2 * u;
  glm::vec4 w(0.5f * (-u3 + 2.0f * u2 - u), 0.5f * (3.0f * u3 - 5.0f * u2 + 2.0f),
              0.5f * (-3.0f * u3 + 4.0f * u2 + u), 0.5f * (u3 - u2));
  if (mode == IntervalMode::kCubicStartsHere) {
    w = glm::vec4(0.0f, w.y + 3.0f * w.x, w.z - 3.0f * w.x, w.w + w.x);
  } else if (mode == IntervalMode::kCubicEndsNext) {
    w = glm::vec4(w.x + w.w, w.y - 3.0f * w.w, w.z + 3.0f * w.w, 0.0f);
  }
  return w;
}

}  // namespace

glm::mat4 emulateFrameMatrix(const BakedPalette& p, uint32_t frame_texel, uint32_t next_texel,
                             float u, uint32_t slot) {
  return emulateFrameMatrix(p, frame_texel, next_texel, u, IntervalMode::kLinear, slot);
}

glm::mat4 emulateFrameMatrix(const BakedPalette& p, uint32_t frame_texel, uint32_t next_texel,
                             float u, IntervalMode mode, uint32_t slot) {
  if (mode != IntervalMode::kLinear) {
    // The frames one stride before and after (the same frame when next == frame).
    const uint32_t step = next_texel - frame_texel, js = slot * p.layout.joint_stride_texels;
    const uint32_t f[4] = {frame_texel - step + js, frame_texel + js, next_texel + js,
                           next_texel + step + js};
    const glm::vec4 w = cubicWeights(u, mode);
    if (p.format == PaletteFormat::kQuatTranslationF32) {
      glm::vec4 q(0.0f), ts(0.0f);
      const glm::vec4 q1 = readTexel(p, f[1]);
      for (int k = 0; k < 4; ++k) {
        const glm::vec4 qk = readTexel(p, f[k]);
        q += w[k] * (glm::dot(qk, q1) < 0.0f ? -qk : qk);  // Frame i's hemisphere.
        ts += w[k] * readTexel(p, f[k] + 1);
      }
      return fromRigid(glm::normalize(q), ts);
    }
    glm::vec4 rows[3] = {glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f)};
    for (int k = 0; k < 4; ++k)
      for (uint32_t r = 0; r < 3; ++r) rows[r] += w[k] * readTexel(p, f[k] + r);
    return fromRows(rows[0], rows[1], rows[2]);
  }
  const uint32_t a = frame_texel + slot * p.layout.joint_stride_texels;
  const uint32_t b = next_texel + slot * p.layout.joint_stride_texels;
  if (p.format == PaletteFormat::kQuatTranslationF32) {
    const glm::vec4 qa = readTexel(p, a);
    glm::vec4 qb = readTexel(p, b);
    if (glm::dot(qa, qb) < 0.0f) qb = -qb;  // Shorter arc.
    const glm::vec4 q = glm::normalize(glm::mix(qa, qb, u));
    return fromRigid(q, glm::mix(readTexel(p, a + 1), readTexel(p, b + 1), u));
  }
  glm::vec4 rows[3];
  for (uint32_t r = 0; r < 3; ++r) rows[r] = glm::mix(readTexel(p, a + r), readTexel(p, b + r), u);
  return fromRows(rows[0], rows[1], rows[2]);
}

Status emulateMorphWeights(const BakedPalette& p, uint32_t frame_texel, uint32_t next_texel,
                           float u, IntervalMode mode, Span<float> out) {
  const PaletteLayout& l = p.layout;
  if (out.size() != l.morph_target_count)
    return {StatusCode::kCountMismatch, strCat("emulateMorphWeights: ", out.size(), " weights for ",
                                               l.morph_target_count, " stored morph targets")};
  const uint32_t step = next_texel - frame_texel;
  for (uint32_t t = 0; t < l.morph_target_count; t += 4) {
    const uint32_t at = l.morph_first_texel + t / 4u;
    glm::vec4 w4;
    if (mode != IntervalMode::kLinear) {
      const uint32_t f[4] = {frame_texel - step + at, frame_texel + at, next_texel + at,
                             next_texel + step + at};
      const glm::vec4 c = cubicWeights(u, mode);
      w4 = glm::vec4(0.0f);
      for (int k = 0; k < 4; ++k) w4 += c[k] * readTexel(p, f[k]);
    } else {
      w4 = glm::mix(readTexel(p, frame_texel + at), readTexel(p, next_texel + at), u);
    }
    for (uint32_t k = 0; k < 4 && t + k < l.morph_target_count; ++k) out[t + k] = w4[int(k)];
  }
  return Status::ok();
}

glm::mat4 emulateSkinningMatrix(const BakedPalette& p, uint32_t clip, const FrameSample& s,
                                uint32_t slot) {
  const PaletteLayout& l = p.layout;
  return emulateFrameMatrix(p, l.texelIndex(clip, s.frame, 0, 0),
                            l.texelIndex(clip, s.next_frame, 0, 0), s.fraction, s.mode, slot);
}

Status emulateSkinningMatrices(const BakedPalette& p, uint32_t clip, const FrameSample& s,
                               Span<glm::mat4> out) {
  if (out.size() != p.skeleton_to_palette.size())
    return {StatusCode::kCountMismatch,
            strCat("emulateSkinningMatrices: ", out.size(), " matrices for ",
                   p.skeleton_to_palette.size(), " joints")};
  if (clip >= p.clips.size() || s.frame >= p.clips[clip].frame_count ||
      s.next_frame >= p.clips[clip].frame_count)
    return {StatusCode::kOutOfRange, "emulateSkinningMatrices: clip or frame out of range"};
  for (size_t j = 0; j < out.size(); ++j) {
    const int32_t slot = p.skeleton_to_palette[j];
    out[j] = slot < 0 ? glm::mat4(1.0f) : emulateSkinningMatrix(p, clip, s, uint32_t(slot));
  }
  return Status::ok();
}

Status emulateSkinning(const SkinnedMesh& mesh, Span<const glm::mat4> matrices,
                       Span<glm::vec3> out_positions, Span<glm::vec3> out_normals,
                       Span<const float> morph_weights) {
  const size_t n = mesh.vertexCount();
  if (out_positions.size() != n || (!out_normals.empty() && out_normals.size() != n) ||
      mesh.joints.size() != n || mesh.weights.size() != n || mesh.normals.size() != n ||
      (!mesh.joints1.empty() && (mesh.joints1.size() != n || mesh.weights1.size() != n)) ||
      (!morph_weights.empty() && morph_weights.size() != mesh.morph_targets.size()))
    return {StatusCode::kCountMismatch, "emulateSkinning: spans do not match the vertex count"};
  // The bind pose with the morph targets added, in float as the shader adds them.
  std::vector<glm::vec3> positions, normals;
  if (!mesh.morph_targets.empty()) {
    const Status s = validateMorphTargets(mesh.morph_targets, n, !mesh.tangents.empty());
    if (!s.isOk()) return s;
    positions = mesh.positions;
    normals = mesh.normals;
    for (size_t t = 0; t < mesh.morph_targets.size(); ++t) {
      const MorphTarget& target = mesh.morph_targets[t];
      const float w = morph_weights.empty() ? target.default_weight : morph_weights[t];
      if (w == 0.0f) continue;
      for (size_t i = 0; i < target.vertices.size(); ++i) {
        positions[target.vertices[i]] += w * target.position_deltas[i];
        if (!target.normal_deltas.empty())
          normals[target.vertices[i]] += w * target.normal_deltas[i];
      }
    }
    // Each moved vertex's normal renormalized once, as the shader does.
    std::vector<uint8_t> moved(n, 0);
    for (const MorphTarget& target : mesh.morph_targets)
      for (uint32_t v : target.vertices) moved[v] = 1;
    for (size_t v = 0; v < n; ++v) {
      if (!moved[v]) continue;
      const float len = glm::length(normals[v]);
      normals[v] = len > 0.0f && std::isfinite(len) ? normals[v] / len : mesh.normals[v];
    }
  }
  const std::vector<glm::vec3>& pos = positions.empty() ? mesh.positions : positions;
  const std::vector<glm::vec3>& nrm = normals.empty() ? mesh.normals : normals;
  const size_t influences = mesh.influenceCount();
  for (size_t v = 0; v < n; ++v) {
    // As the shader: blend the influences' matrices (zero weights skipped), then transform.
    glm::mat4 m(0.0f);
    for (size_t i = 0; i < influences; ++i) {
      const Influence in = mesh.influence(v, i);
      const float w = in.weight;
      if (w == 0.0f) continue;
      const uint32_t j = in.joint;
      if (j >= matrices.size())
        return {StatusCode::kOutOfRange, strCat("emulateSkinning: vertex ", v, " joint ", j)};
      m += matrices[j] * w;
    }
    out_positions[v] = glm::vec3(m * glm::vec4(pos[v], 1.0f));
    if (!out_normals.empty()) out_normals[v] = detail::skinNormal(glm::mat3(m), nrm[v]);
  }
  return Status::ok();
}

}  // namespace si
