// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd/live_pose_rows.h"

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_access.hpp>

#include "core/palette_texel.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#define SI_LIVE_ROWS_SSE2 1
#endif

namespace si::detail {

size_t firstBadJointReference(Span<const glm::mat4> skinning, float range) {
  for (size_t k = 0; k < skinning.size(); ++k) {
    const glm::mat4& m = skinning[k];
    bool bad = m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r) bad |= !(std::fabs(m[c][r]) <= range);
    if (bad) return k;
  }
  return skinning.size();
}

void storeJointRowsReference(PaletteFormat format, Span<const glm::mat4> skinning,
                             uint32_t joint_stride_texels, uint8_t* frame) {
  for (size_t j = 0; j < skinning.size(); ++j)
    for (uint32_t row = 0; row < 3; ++row)
      storeFormatTexel(format, frame, j * joint_stride_texels + row,
                       glm::row(skinning[j], int(row)));
}

std::vector<JointBox> jointBoxes(Span<const Aabb> joint_bounds) {
  std::vector<JointBox> out(joint_bounds.size());
  for (size_t j = 0; j < joint_bounds.size(); ++j) {
    const Aabb& b = joint_bounds[j];
    if (b.empty()) continue;
    out[j].center = glm::vec4(0.5f * (b.min + b.max), 0.0f);
    out[j].half = glm::vec4(0.5f * (b.max - b.min), 0.0f);
  }
  return out;
}

Aabb poseBoxReference(Span<const glm::mat4> skinning, Span<const JointBox> joints) {
  Aabb box;
  for (size_t j = 0; j < skinning.size(); ++j) {
    const JointBox& b = joints[j];
    if (b.half.x < 0.0f) continue;
    const glm::mat4& m = skinning[j];
    const glm::vec3 center = glm::vec3(m[0]) * b.center.x + glm::vec3(m[1]) * b.center.y +
                             glm::vec3(m[2]) * b.center.z + glm::vec3(m[3]);
    const glm::vec3 half = glm::abs(glm::vec3(m[0])) * b.half.x +
                           glm::abs(glm::vec3(m[1])) * b.half.y +
                           glm::abs(glm::vec3(m[2])) * b.half.z;
    box.extend(center - half);
    box.extend(center + half);
  }
  return box;
}

#if SI_LIVE_ROWS_SSE2

namespace {

// Four floats, finite and of magnitude at most 65504, as half floats rounded to nearest even
// (what floatToHalf gives them), each in its lane's low 16 bits.
inline __m128i halvesOf(__m128 v) {
  const __m128i u = _mm_castps_si128(v);
  const __m128i sign = _mm_and_si128(_mm_srli_epi32(u, 16), _mm_set1_epi32(0x8000));
  const __m128i a = _mm_and_si128(u, _mm_set1_epi32(0x7FFFFFFF));
  // A normal half (2^-14 and up): the exponent rebased from 127 to 15 and the mantissa's 13 low
  // bits rounded off, to nearest even (adding 0xFFF, and one more when the kept bits are odd;
  // a carry rounds up into the exponent).
  const __m128i odd = _mm_and_si128(_mm_srli_epi32(a, 13), _mm_set1_epi32(1));
  const __m128i normal =
      _mm_srli_epi32(_mm_add_epi32(_mm_add_epi32(a, _mm_set1_epi32(0xFFF - (112 << 23))), odd), 13);
  // A subnormal half (below 2^-14, steps of 2^-24): added to 0.5, whose float step is 2^-24,
  // the sum is rounded to that step (to nearest even) by the addition; its mantissa bits past
  // 0.5's are then the half's (1024, the smallest normal half, where it rounds up to it).
  const __m128 base = _mm_set1_ps(0.5f);
  const __m128i subnormal = _mm_sub_epi32(_mm_castps_si128(_mm_add_ps(_mm_castsi128_ps(a), base)),
                                          _mm_castps_si128(base));
  const __m128i is_subnormal = _mm_cmplt_epi32(a, _mm_set1_epi32(113 << 23));
  return _mm_or_si128(sign, _mm_or_si128(_mm_and_si128(is_subnormal, subnormal),
                                         _mm_andnot_si128(is_subnormal, normal)));
}

// Two rows of halves (halvesOf) packed into eight 16-bit values: each lane sign-extended from
// its low 16 bits first, so the saturating pack keeps them exactly.
inline __m128i packHalves(__m128i a, __m128i b) {
  return _mm_packs_epi32(_mm_srai_epi32(_mm_slli_epi32(a, 16), 16),
                         _mm_srai_epi32(_mm_slli_epi32(b, 16), 16));
}

// The union of joint boxes carried by their matrices (poseBoxReference's arithmetic, in its
// order, four lanes at a time: the fourth carries the matrices' last row and is dropped).
struct BoxLanes {
  __m128 lo = _mm_set1_ps(1e30f), hi = _mm_set1_ps(-1e30f);
  void add(__m128 c0, __m128 c1, __m128 c2, __m128 c3, const JointBox& b) {
    const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
    const __m128 c = _mm_loadu_ps(&b.center[0]), h = _mm_loadu_ps(&b.half[0]);
    const __m128 center =
        _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(c0, _mm_shuffle_ps(c, c, 0x00)),
                                         _mm_mul_ps(c1, _mm_shuffle_ps(c, c, 0x55))),
                              _mm_mul_ps(c2, _mm_shuffle_ps(c, c, 0xAA))),
                   c3);
    const __m128 half =
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_and_ps(c0, magnitude), _mm_shuffle_ps(h, h, 0x00)),
                              _mm_mul_ps(_mm_and_ps(c1, magnitude), _mm_shuffle_ps(h, h, 0x55))),
                   _mm_mul_ps(_mm_and_ps(c2, magnitude), _mm_shuffle_ps(h, h, 0xAA)));
    lo = _mm_min_ps(lo, _mm_sub_ps(center, half));
    hi = _mm_max_ps(hi, _mm_add_ps(center, half));
  }
  Aabb box() const {
    float l[4], u[4];
    _mm_storeu_ps(l, lo);
    _mm_storeu_ps(u, hi);
    Aabb out;
    out.min = glm::vec3(l[0], l[1], l[2]);
    out.max = glm::vec3(u[0], u[1], u[2]);
    return out;
  }
};

}  // namespace

size_t firstBadJoint(Span<const glm::mat4> skinning, float range) {
  // Column by column, no transpose: rows 0 to 2 of each at most `range` in magnitude (not <=:
  // past it, or not a number, the comparison then unordered), row 3 equal to the identity's.
  const float inf = std::numeric_limits<float>::infinity();
  const __m128 limit = _mm_setr_ps(range, range, range, inf);
  const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
  const __m128 last = _mm_castsi128_ps(_mm_setr_epi32(0, 0, 0, -1));
  const __m128 zero = _mm_setzero_ps(), one = _mm_setr_ps(0.0f, 0.0f, 0.0f, 1.0f);
  for (size_t k = 0; k < skinning.size(); ++k) {
    const glm::mat4& m = skinning[k];
    __m128 bad = zero;
    for (int c = 0; c < 4; ++c) {
      const __m128 col = _mm_loadu_ps(&m[c][0]);
      bad = _mm_or_ps(bad, _mm_cmpnle_ps(_mm_and_ps(col, magnitude), limit));
      bad = _mm_or_ps(bad, _mm_and_ps(last, _mm_cmpneq_ps(col, c == 3 ? one : zero)));
    }
    if (_mm_movemask_ps(bad) != 0) return k;
  }
  return skinning.size();
}

Aabb storePose(PaletteFormat format, Span<const glm::mat4> skinning, uint32_t joint_stride_texels,
               Span<const JointBox> joints, uint8_t* frame) {
  BoxLanes box;
  const bool bounded = !joints.empty();
  const bool half = format == PaletteFormat::kMatrix3x4F16;
  const size_t texel_bytes = half ? 8 : 16;
  for (size_t j = 0; j < skinning.size(); ++j) {
    // The matrix's columns, bounded, then transposed in place into its rows.
    const glm::mat4& m = skinning[j];
    __m128 r0 = _mm_loadu_ps(&m[0][0]), r1 = _mm_loadu_ps(&m[1][0]);
    __m128 r2 = _mm_loadu_ps(&m[2][0]), r3 = _mm_loadu_ps(&m[3][0]);
    if (bounded && joints[j].half.x >= 0.0f) box.add(r0, r1, r2, r3, joints[j]);
    _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
    uint8_t* out = frame + j * joint_stride_texels * texel_bytes;
    if (half) {
      const __m128i row2 = halvesOf(r2);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out), packHalves(halvesOf(r0), halvesOf(r1)));
      _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 16), packHalves(row2, row2));
    } else {
      float* rows = reinterpret_cast<float*>(out);
      _mm_storeu_ps(rows, r0);
      _mm_storeu_ps(rows + 4, r1);
      _mm_storeu_ps(rows + 8, r2);
    }
  }
  return bounded ? box.box() : Aabb();
}

#else  // No SSE2: one value at a time.

size_t firstBadJoint(Span<const glm::mat4> skinning, float range) {
  return firstBadJointReference(skinning, range);
}

Aabb storePose(PaletteFormat format, Span<const glm::mat4> skinning, uint32_t joint_stride_texels,
               Span<const JointBox> joints, uint8_t* frame) {
  storeJointRowsReference(format, skinning, joint_stride_texels, frame);
  return joints.empty() ? Aabb() : poseBoxReference(skinning, joints);
}

#endif

}  // namespace si::detail
