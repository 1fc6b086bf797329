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
#if defined(__SSE2__) && defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>  // F16C, for functions built for it alone (target attribute).
#define SI_LIVE_ROWS_F16C 1
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
  bool nan = false;
  for (size_t j = 0; j < skinning.size(); ++j) {
    const JointBox& b = joints[j];
    if (b.half.x < 0.0f) continue;
    const glm::mat4& m = skinning[j];
    const glm::vec3 center = glm::vec3(m[0]) * b.center.x + glm::vec3(m[1]) * b.center.y +
                             glm::vec3(m[2]) * b.center.z + glm::vec3(m[3]);
    const glm::vec3 half = glm::abs(glm::vec3(m[0])) * b.half.x +
                           glm::abs(glm::vec3(m[1])) * b.half.y +
                           glm::abs(glm::vec3(m[2])) * b.half.z;
    nan |= std::isnan(center.x) || std::isnan(center.y) || std::isnan(center.z);
    box.extend(center - half);
    box.extend(center + half);
  }
  if (nan) box.min = box.max = glm::vec3(std::numeric_limits<float>::quiet_NaN());
  return box;
}

namespace {

size_t storePoseReference(PaletteFormat format, Span<const glm::mat4> skinning,
                          uint32_t joint_stride_texels, Span<const JointBox> joints, float range,
                          uint8_t* frame, Aabb* box) {
  const size_t bad = firstBadJointReference(skinning, range);
  if (bad < skinning.size()) return bad;
  storeJointRowsReference(format, skinning, joint_stride_texels, frame);
  *box = joints.empty() ? Aabb() : poseBoxReference(skinning, joints);
  return skinning.size();
}

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

// The one pass: each matrix's columns loaded once, checked, carried into the box and stored
// by `rows` (inlined into its caller, so that F16C's caller builds it for F16C).
template <class Rows>
__attribute__((always_inline)) inline size_t storeLanes(Span<const glm::mat4> skinning,
                                                        size_t joint_bytes,
                                                        Span<const JointBox> joints, float range,
                                                        uint8_t* frame, Aabb* box, Rows rows) {
  const __m128 limit = _mm_setr_ps(range, range, range, std::numeric_limits<float>::infinity());
  BoxLanes lanes;
  const bool bounded = !joints.empty();
  for (size_t j = 0; j < skinning.size(); ++j) {
    const glm::mat4& m = skinning[j];
    const __m128 c0 = _mm_loadu_ps(&m[0][0]), c1 = _mm_loadu_ps(&m[1][0]);
    const __m128 c2 = _mm_loadu_ps(&m[2][0]), c3 = _mm_loadu_ps(&m[3][0]);
    if (badColumns(c0, c1, c2, c3, limit)) return j;
    if (bounded && joints[j].half.x >= 0.0f) lanes.add(c0, c1, c2, c3, joints[j]);
    rows(c0, c1, c2, c3, frame + j * joint_bytes);
  }
  *box = bounded ? lanes.box() : Aabb();
  return skinning.size();
}

size_t storePoseSse2(PaletteFormat format, Span<const glm::mat4> skinning,
                     uint32_t joint_stride_texels, Span<const JointBox> joints, float range,
                     uint8_t* frame, Aabb* box) {
  const size_t joint_bytes = size_t(joint_stride_texels) * bytesPerTexel(format);
  if (format == PaletteFormat::kMatrix3x4F16)
    return storeLanes(skinning, joint_bytes, joints, range, frame, box, Sse2HalfRows());
  return storeLanes(skinning, joint_bytes, joints, range, frame, box, FloatRows());
}

#endif  // SI_LIVE_ROWS_SSE2

#if SI_LIVE_ROWS_F16C

// Half-float rows through F16C: each column converted (to nearest even, as floatToHalf
// rounds; every value is within the half's range, checked first), then the four columns of
// four halves interleaved into rows.
struct F16cHalfRows {
  __attribute__((target("avx,f16c"))) void operator()(__m128 c0, __m128 c1, __m128 c2, __m128 c3,
                                                      uint8_t* out) const {
    const __m128i h0 = _mm_cvtps_ph(c0, _MM_FROUND_TO_NEAREST_INT);
    const __m128i h1 = _mm_cvtps_ph(c1, _MM_FROUND_TO_NEAREST_INT);
    const __m128i h2 = _mm_cvtps_ph(c2, _MM_FROUND_TO_NEAREST_INT);
    const __m128i h3 = _mm_cvtps_ph(c3, _MM_FROUND_TO_NEAREST_INT);
    const __m128i c01 = _mm_unpacklo_epi16(h0, h1);  // Rows 0 to 3 of columns 0 and 1.
    const __m128i c23 = _mm_unpacklo_epi16(h2, h3);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_unpacklo_epi32(c01, c23));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 16), _mm_unpackhi_epi32(c01, c23));
  }
};

// Two joints at a time in AVX's eight lanes (the first's columns in the low four, the
// second's in the high four): checked as badColumns checks, their boxes carried as BoxLanes
// carries them, their rows stored as FloatRows stores them or converted by F16C; an odd last
// joint four lanes at a time.
__attribute__((target("avx,f16c"))) size_t storePoseF16c(PaletteFormat format,
                                                         Span<const glm::mat4> skinning,
                                                         uint32_t joint_stride_texels,
                                                         Span<const JointBox> joints, float range,
                                                         uint8_t* frame, Aabb* box) {
  const bool half = format == PaletteFormat::kMatrix3x4F16;
  const size_t joint_bytes = size_t(joint_stride_texels) * bytesPerTexel(format);
  const size_t n = skinning.size();
  const bool bounded = !joints.empty();
  const float inf = std::numeric_limits<float>::infinity();
  const __m256 magnitude = _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF));
  const __m256 limit = _mm256_setr_ps(range, range, range, inf, range, range, range, inf);
  const __m256 zero = _mm256_setzero_ps();
  const __m256 last_row23 = _mm256_setr_ps(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f);
  const __m256 last = _mm256_castsi256_ps(_mm256_setr_epi32(0, 0, 0, -1, 0, 0, 0, -1));
  __m256 lo = _mm256_set1_ps(1e30f), hi = _mm256_set1_ps(-1e30f), nan = zero;
  size_t j = 0;
  for (; j + 2 <= n; j += 2) {
    const float* a = &skinning[j][0][0];
    const float* b = &skinning[j + 1][0][0];
    const __m256 a01 = _mm256_loadu_ps(a), a23 = _mm256_loadu_ps(a + 8);
    const __m256 b01 = _mm256_loadu_ps(b), b23 = _mm256_loadu_ps(b + 8);
    __m256 bad = _mm256_or_ps(_mm256_cmp_ps(_mm256_and_ps(a01, magnitude), limit, _CMP_NLE_UQ),
                              _mm256_cmp_ps(_mm256_and_ps(a23, magnitude), limit, _CMP_NLE_UQ));
    bad = _mm256_or_ps(bad, _mm256_cmp_ps(_mm256_and_ps(b01, magnitude), limit, _CMP_NLE_UQ));
    bad = _mm256_or_ps(bad, _mm256_cmp_ps(_mm256_and_ps(b23, magnitude), limit, _CMP_NLE_UQ));
    __m256 row3 = _mm256_or_ps(_mm256_cmp_ps(a01, zero, _CMP_NEQ_UQ),
                               _mm256_cmp_ps(a23, last_row23, _CMP_NEQ_UQ));
    row3 = _mm256_or_ps(row3, _mm256_or_ps(_mm256_cmp_ps(b01, zero, _CMP_NEQ_UQ),
                                           _mm256_cmp_ps(b23, last_row23, _CMP_NEQ_UQ)));
    if (_mm256_movemask_ps(_mm256_or_ps(bad, _mm256_and_ps(last, row3))) != 0)
      return j + firstBadJointReference(Span<const glm::mat4>(&skinning[j], 2), range);
    // Column k of both joints: [first's | second's].
    const __m256 c0 = _mm256_permute2f128_ps(a01, b01, 0x20);
    const __m256 c1 = _mm256_permute2f128_ps(a01, b01, 0x31);
    const __m256 c2 = _mm256_permute2f128_ps(a23, b23, 0x20);
    const __m256 c3 = _mm256_permute2f128_ps(a23, b23, 0x31);
    if (bounded) {
      const JointBox& ja = joints[j];
      const JointBox& jb = joints[j + 1];
      const __m256 c = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(&ja.center[0])),
                                            _mm_loadu_ps(&jb.center[0]), 1);
      const __m256 h = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(&ja.half[0])),
                                            _mm_loadu_ps(&jb.half[0]), 1);
      const __m256 center = _mm256_add_ps(
          _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(c0, _mm256_shuffle_ps(c, c, 0x00)),
                                      _mm256_mul_ps(c1, _mm256_shuffle_ps(c, c, 0x55))),
                        _mm256_mul_ps(c2, _mm256_shuffle_ps(c, c, 0xAA))),
          c3);
      const __m256 hx = _mm256_shuffle_ps(h, h, 0x00);
      const __m256 extent = _mm256_add_ps(
          _mm256_add_ps(_mm256_mul_ps(_mm256_and_ps(c0, magnitude), hx),
                        _mm256_mul_ps(_mm256_and_ps(c1, magnitude), _mm256_shuffle_ps(h, h, 0x55))),
          _mm256_mul_ps(_mm256_and_ps(c2, magnitude), _mm256_shuffle_ps(h, h, 0xAA)));
      // A joint with an empty box (half extents -1) adds nothing: its corners are made NaN,
      // which min and max pass over. Its centre is its matrix's translation, a number.
      const __m256 empty = _mm256_cmp_ps(hx, zero, _CMP_LT_OQ);
      lo = _mm256_min_ps(_mm256_or_ps(_mm256_sub_ps(center, extent), empty), lo);
      hi = _mm256_max_ps(_mm256_or_ps(_mm256_add_ps(center, extent), empty), hi);
      nan = _mm256_or_ps(nan, _mm256_cmp_ps(center, center, _CMP_UNORD_Q));
    }
    uint8_t* first = frame + j * joint_bytes;
    uint8_t* second = first + joint_bytes;
    if (half) {
      const __m128i h0 = _mm256_cvtps_ph(c0, _MM_FROUND_TO_NEAREST_INT);
      const __m128i h1 = _mm256_cvtps_ph(c1, _MM_FROUND_TO_NEAREST_INT);
      const __m128i h2 = _mm256_cvtps_ph(c2, _MM_FROUND_TO_NEAREST_INT);
      const __m128i h3 = _mm256_cvtps_ph(c3, _MM_FROUND_TO_NEAREST_INT);
      // Rows 0 to 3 of columns 0 and 1 (2 and 3), of the first joint and of the second.
      const __m128i p01 = _mm_unpacklo_epi16(h0, h1), q01 = _mm_unpackhi_epi16(h0, h1);
      const __m128i p23 = _mm_unpacklo_epi16(h2, h3), q23 = _mm_unpackhi_epi16(h2, h3);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(first), _mm_unpacklo_epi32(p01, p23));
      _mm_storel_epi64(reinterpret_cast<__m128i*>(first + 16), _mm_unpackhi_epi32(p01, p23));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(second), _mm_unpacklo_epi32(q01, q23));
      _mm_storel_epi64(reinterpret_cast<__m128i*>(second + 16), _mm_unpackhi_epi32(q01, q23));
    } else {  // Both matrices transposed at once, each in its four lanes.
      const __m256 t0 = _mm256_unpacklo_ps(c0, c1), t1 = _mm256_unpackhi_ps(c0, c1);
      const __m256 t2 = _mm256_unpacklo_ps(c2, c3), t3 = _mm256_unpackhi_ps(c2, c3);
      const __m256 r0 = _mm256_shuffle_ps(t0, t2, 0x44), r1 = _mm256_shuffle_ps(t0, t2, 0xEE);
      const __m256 r2 = _mm256_shuffle_ps(t1, t3, 0x44);
      float* fa = reinterpret_cast<float*>(first);
      float* fb = reinterpret_cast<float*>(second);
      _mm_storeu_ps(fa, _mm256_castps256_ps128(r0));
      _mm_storeu_ps(fa + 4, _mm256_castps256_ps128(r1));
      _mm_storeu_ps(fa + 8, _mm256_castps256_ps128(r2));
      _mm_storeu_ps(fb, _mm256_extractf128_ps(r0, 1));
      _mm_storeu_ps(fb + 4, _mm256_extractf128_ps(r1, 1));
      _mm_storeu_ps(fb + 8, _mm256_extractf128_ps(r2, 1));
    }
  }
  BoxLanes lanes;  // The pairs' boxes, and an odd last joint's.
  lanes.lo = _mm_min_ps(_mm256_castps256_ps128(lo), _mm256_extractf128_ps(lo, 1));
  lanes.hi = _mm_max_ps(_mm256_castps256_ps128(hi), _mm256_extractf128_ps(hi, 1));
  lanes.nan = _mm_or_ps(_mm256_castps256_ps128(nan), _mm256_extractf128_ps(nan, 1));
  if (j < n) {
    const glm::mat4& m = skinning[j];
    const __m128 c0 = _mm_loadu_ps(&m[0][0]), c1 = _mm_loadu_ps(&m[1][0]);
    const __m128 c2 = _mm_loadu_ps(&m[2][0]), c3 = _mm_loadu_ps(&m[3][0]);
    if (badColumns(c0, c1, c2, c3, _mm_setr_ps(range, range, range, inf))) return j;
    if (bounded && joints[j].half.x >= 0.0f) lanes.add(c0, c1, c2, c3, joints[j]);
    if (half)
      F16cHalfRows()(c0, c1, c2, c3, frame + j * joint_bytes);
    else
      FloatRows()(c0, c1, c2, c3, frame + j * joint_bytes);
  }
  *box = bounded ? lanes.box() : Aabb();
  return n;
}

bool cpuRunsF16c() {
  // GCC's and Clang's runtimes report AVX (and so F16C's VEX encoding) only where the OS
  // saves its state.
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx") && __builtin_cpu_supports("f16c");
}

#endif  // SI_LIVE_ROWS_F16C

PoseRowsIsa bestIsa() {
  static const PoseRowsIsa best = runs(PoseRowsIsa::kF16c)   ? PoseRowsIsa::kF16c
                                  : runs(PoseRowsIsa::kSse2) ? PoseRowsIsa::kSse2
                                                             : PoseRowsIsa::kReference;
  return best;
}

}  // namespace

bool runs(PoseRowsIsa isa) {
  switch (isa) {
    case PoseRowsIsa::kSse2:
#if SI_LIVE_ROWS_SSE2
      return true;
#else
      return false;
#endif
    case PoseRowsIsa::kF16c: {
#if SI_LIVE_ROWS_F16C
      static const bool f16c = cpuRunsF16c();
      return f16c;
#else
      return false;
#endif
    }
    case PoseRowsIsa::kReference:
    case PoseRowsIsa::kBest:
      return true;
  }
  return false;
}

size_t storePose(PaletteFormat format, Span<const glm::mat4> skinning, uint32_t joint_stride_texels,
                 Span<const JointBox> joints, float range, uint8_t* frame, Aabb* box,
                 PoseRowsIsa isa) {
  if (isa == PoseRowsIsa::kBest) isa = bestIsa();
  switch (isa) {
#if SI_LIVE_ROWS_F16C
    case PoseRowsIsa::kF16c:
      return storePoseF16c(format, skinning, joint_stride_texels, joints, range, frame, box);
#endif
#if SI_LIVE_ROWS_SSE2
    case PoseRowsIsa::kSse2:
      return storePoseSse2(format, skinning, joint_stride_texels, joints, range, frame, box);
#endif
    default:
      return storePoseReference(format, skinning, joint_stride_texels, joints, range, frame, box);
  }
}

}  // namespace si::detail
