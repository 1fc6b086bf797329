// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// storePose two joints at a time in AVX's eight lanes, half floats converted by F16C
// (crowd/live_pose_lanes.h). Each function here is built for AVX and F16C by its target
// attribute and runs only where cpuRunsF16c() says so; the file is built as the rest.
#include <limits>

#include "crowd/live_pose_lanes.h"
#include "si/core/baked_palette.h"

#if SI_LIVE_ROWS_F16C
#include <cpuid.h>
#include <immintrin.h>

namespace si::detail {
namespace {

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

}  // namespace

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
  // CPUID leaf 1 names AVX and F16C; their VEX encoding runs only where the OS saves the YMM
  // state (OSXSAVE, then XCR0's SSE and AVX bits). Asked directly: Clang's
  // __builtin_cpu_supports knows no "f16c".
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (__get_cpuid(1, &eax, &ebx, &ecx, &edx) == 0) return false;
  const unsigned needed = bit_AVX | bit_F16C | bit_OSXSAVE;
  if ((ecx & needed) != needed) return false;
  unsigned xcr0 = 0, high = 0;
  __asm__("xgetbv" : "=a"(xcr0), "=d"(high) : "c"(0));
  return (xcr0 & 6u) == 6u;
}

}  // namespace si::detail

#endif  // SI_LIVE_ROWS_F16C
