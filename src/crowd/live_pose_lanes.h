// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What storePose's fast variants (crowd/live_pose_rows.h) are built from: a joint checked, its
// box carried and its rows stored four floats at a time (SSE2, every x86-64), and the variants
// themselves, SSE2's (live_pose_rows_sse2.cpp) and AVX with F16C's (live_pose_rows_avx.cpp,
// built for AVX function by function: the rest of the library runs on any x86-64). Internal to
// the crowd layer. No GL.

#include <cstddef>
#include <cstdint>

#include "crowd/live_pose_rows.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#define SI_LIVE_ROWS_SSE2 1
#endif
#if defined(__SSE2__) && defined(__x86_64__) && defined(__GNUC__)
#define SI_LIVE_ROWS_F16C 1
#endif

namespace si::detail {

#if SI_LIVE_ROWS_SSE2

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
// order, four lanes at a time: the fourth carries the matrices' last row and is dropped). As
// Aabb::extend, a corner that is not a number leaves the box as it was (min and max take the
// box's side then); a centre that is not a number (an overflow's inf - inf) makes it one.
struct BoxLanes {
  __m128 lo = _mm_set1_ps(1e30f), hi = _mm_set1_ps(-1e30f), nan = _mm_setzero_ps();
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
    lo = _mm_min_ps(_mm_sub_ps(center, half), lo);
    hi = _mm_max_ps(_mm_add_ps(center, half), hi);
    nan = _mm_or_ps(nan, _mm_cmpunord_ps(center, center));
  }
  Aabb box() const {
    float l[4], u[4];
    _mm_storeu_ps(l, _mm_or_ps(lo, nan));  // All bits set: a NaN.
    _mm_storeu_ps(u, _mm_or_ps(hi, nan));
    Aabb out;
    out.min = glm::vec3(l[0], l[1], l[2]);
    out.max = glm::vec3(u[0], u[1], u[2]);
    return out;
  }
};

// Whether any of a matrix's columns breaks firstBadJointReference's rule: rows 0 to 2 at most
// `limit` in magnitude (not <=: past it, or not a number, the comparison then unordered), row 3
// equal to the identity's.
inline bool badColumns(__m128 c0, __m128 c1, __m128 c2, __m128 c3, __m128 limit) {
  const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
  const __m128 last = _mm_castsi128_ps(_mm_setr_epi32(0, 0, 0, -1));
  const __m128 zero = _mm_setzero_ps(), one = _mm_setr_ps(0.0f, 0.0f, 0.0f, 1.0f);
  __m128 bad = _mm_or_ps(_mm_cmpnle_ps(_mm_and_ps(c0, magnitude), limit),
                         _mm_cmpnle_ps(_mm_and_ps(c1, magnitude), limit));
  bad = _mm_or_ps(bad, _mm_cmpnle_ps(_mm_and_ps(c2, magnitude), limit));
  bad = _mm_or_ps(bad, _mm_cmpnle_ps(_mm_and_ps(c3, magnitude), limit));
  __m128 row3 = _mm_or_ps(_mm_cmpneq_ps(c0, zero), _mm_cmpneq_ps(c1, zero));
  row3 = _mm_or_ps(row3, _mm_or_ps(_mm_cmpneq_ps(c2, zero), _mm_cmpneq_ps(c3, one)));
  return _mm_movemask_ps(_mm_or_ps(bad, _mm_and_ps(last, row3))) != 0;
}

// A joint's three rows stored from its four columns: as floats, or as half floats through
// halvesOf.
struct FloatRows {
  void operator()(__m128 c0, __m128 c1, __m128 c2, __m128 c3, uint8_t* out) const {
    _MM_TRANSPOSE4_PS(c0, c1, c2, c3);
    float* rows = reinterpret_cast<float*>(out);
    _mm_storeu_ps(rows, c0);
    _mm_storeu_ps(rows + 4, c1);
    _mm_storeu_ps(rows + 8, c2);
  }
};
struct Sse2HalfRows {
  void operator()(__m128 c0, __m128 c1, __m128 c2, __m128 c3, uint8_t* out) const {
    _MM_TRANSPOSE4_PS(c0, c1, c2, c3);
    const __m128i row2 = halvesOf(c2);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), packHalves(halvesOf(c0), halvesOf(c1)));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 16), packHalves(row2, row2));
  }
};

/// storePose one joint at a time in SSE2's four lanes.
size_t storePoseSse2(PaletteFormat format, Span<const glm::mat4> skinning,
                     uint32_t joint_stride_texels, Span<const JointBox> joints, float range,
                     uint8_t* frame, Aabb* box);

#endif  // SI_LIVE_ROWS_SSE2

#if SI_LIVE_ROWS_F16C
/// storePose two joints at a time in AVX's eight lanes, half floats converted by F16C. Only
/// where cpuRunsF16c().
size_t storePoseF16c(PaletteFormat format, Span<const glm::mat4> skinning,
                     uint32_t joint_stride_texels, Span<const JointBox> joints, float range,
                     uint8_t* frame, Aabb* box);
/// Whether this CPU (and OS: AVX state saved) runs storePoseF16c.
bool cpuRunsF16c();
#endif  // SI_LIVE_ROWS_F16C

}  // namespace si::detail
