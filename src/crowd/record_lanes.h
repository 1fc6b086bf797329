// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Instance records for 8 instances at once, in GCC/Clang vector types: the world rows
// (glm::mat3_cast * scale, the camera-relative translation), clip A's time (from the crowd
// clock, looped or clamped), its uniform-grid frame and fraction and the record words of one
// clip playing, lane by lane the same operations as frame_builder.cpp's scalarRecord,
// playback.h's localTime and fastSample; then the records stored 8 at a time. A time the lanes
// cannot compute (not finite, or a loop past 2^53 intervals) is marked in scalar[]; the caller
// finishes per lane what the one-clip words do not cover (a crossfade, animation LOD, a clip
// with frame times, whose frame it finds from time[]).

#include <cstdint>
#include <cstring>

namespace si::detail {

inline constexpr uint32_t kRecordLanes = 8;
/// Instances gathered before the vector work (see cull::kBlock).
inline constexpr uint32_t kRecordBlock = 64;

/// A block of instances' inputs (structure of arrays) and outputs.
struct RecordLanes {
  alignas(32) float rx[kRecordBlock], ry[kRecordBlock], rz[kRecordBlock], qx[kRecordBlock],
      qy[kRecordBlock], qz[kRecordBlock], qw[kRecordBlock], s[kRecordBlock];
  alignas(64) double start_time[kRecordBlock], start_clock[kRecordBlock], speed[kRecordBlock];
  alignas(64) double duration[kRecordBlock], inv_duration[kRecordBlock], inv_interval[kRecordBlock],
      last_interval[kRecordBlock];
  alignas(32) int32_t loop[kRecordBlock];    // -1: the clip loops; 0: it plays once.
  alignas(32) int32_t scalar[kRecordBlock];  // In: -1 marks a lane for the caller regardless.
  alignas(32) uint32_t first_texel[kRecordBlock];  // The clip's first frame texel.
  alignas(32) uint32_t color[kRecordBlock];        // The appearance word.
  // Out: the world rows, the frame index and fraction; scalar[] also marks lanes whose time
  // needs the scalar path.
  alignas(32) float rows[3][3][kRecordBlock];  // rows[row][column]: rotation * scale.
  alignas(32) int32_t frame[kRecordBlock];
  alignas(32) float fraction[kRecordBlock];
  alignas(64) double time[kRecordBlock];  // The clip-local time (localTime) of each lane.
  // Each record's frames and blend words, for one clip on a uniform grid of linear intervals
  // (the caller replaces them where the lane needs more; storeRecordLanes stores them).
  alignas(32) uint32_t frames[4][kRecordBlock];
  alignas(32) uint32_t blend[4][kRecordBlock];
};

/// Computes the outputs of the 8 lanes of `l` from `base` on at crowd clock `clock`, frames
/// `stride` texels apart. Always inlined: the vector types never cross a call.
__attribute__((always_inline)) inline void computeRecordLanes(double clock, uint32_t stride,
                                                              RecordLanes& l, uint32_t base) {
  typedef float f8 __attribute__((vector_size(32)));
#define SI_LOAD(dst, src) std::memcpy(&(dst), (src) + base, sizeof(dst))
#define SI_BLEND(m, a, b) (((m) & (a)) | (~(m) & (b)))
  // World rows: glm::mat3_cast(q) * s, transposed into rows.
  f8 qx, qy, qz, qw, s;
  SI_LOAD(qx, l.qx);
  SI_LOAD(qy, l.qy);
  SI_LOAD(qz, l.qz);
  SI_LOAD(qw, l.qw);
  SI_LOAD(s, l.s);
  const f8 qxx = qx * qx, qyy = qy * qy, qzz = qz * qz, qxz = qx * qz, qxy = qx * qy;
  const f8 qyz = qy * qz, qwx = qw * qx, qwy = qw * qy, qwz = qw * qz;
  const f8 m[3][3] = {
      {(1.0f - 2.0f * (qyy + qzz)) * s, (2.0f * (qxy + qwz)) * s, (2.0f * (qxz - qwy)) * s},
      {(2.0f * (qxy - qwz)) * s, (1.0f - 2.0f * (qxx + qzz)) * s, (2.0f * (qyz + qwx)) * s},
      {(2.0f * (qxz + qwy)) * s, (2.0f * (qyz - qwx)) * s, (1.0f - 2.0f * (qxx + qyy)) * s}};
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      std::memcpy(l.rows[row][col] + base, &m[col][row], sizeof(f8));

  // Playback time (localTime) and the frame sample, 4 lanes at a time in double.
  typedef double d4 __attribute__((vector_size(32)));
  typedef int64_t l4 __attribute__((vector_size(32)));
  typedef int32_t i4 __attribute__((vector_size(16)));
  typedef float f4 __attribute__((vector_size(16)));
  i4 frame_half[2];
  f4 fraction_half[2];
  for (uint32_t half = base; half < base + 8; half += 4) {
#define SI_LOAD4(dst, src) std::memcpy(&(dst), (src) + half, sizeof(dst))
#define SI_DBLEND(m, a, b) ((d4)SI_BLEND((m), (l4)(a), (l4)(b)))
    d4 start_time, start_clock, speed, duration, inv_duration, inv_interval, last;
    SI_LOAD4(start_time, l.start_time);
    SI_LOAD4(start_clock, l.start_clock);
    SI_LOAD4(speed, l.speed);
    SI_LOAD4(duration, l.duration);
    SI_LOAD4(inv_duration, l.inv_duration);
    SI_LOAD4(inv_interval, l.inv_interval);
    SI_LOAD4(last, l.last_interval);
    i4 scalar_in, loop_in;
    SI_LOAD4(scalar_in, l.scalar);
    SI_LOAD4(loop_in, l.loop);
    const d4 zero = {}, one = zero + 1.0;
    const d4 t = start_time + (clock - start_clock) * speed;
    l4 scalar = __builtin_convertvector(scalar_in, l4);
    scalar |= ~(duration > zero) | ~((t - t) == zero);  // No duration, or t not finite.
    // floor(x), exact: rounding by adding and subtracting 2^52 (with x's sign), then one down
    // where that went up; |x| >= 2^52 is already an integer.
    const d4 x = t * inv_duration;
    const d4 big = zero + 4503599627370496.0;
    const d4 magic = SI_DBLEND(x < zero, -big, big);
    const d4 rounded = (x + magic) - magic;
    d4 fl = SI_DBLEND(rounded > x, rounded - one, rounded);
    fl = SI_DBLEND((x >= big) | (x <= -big), x, fl);
    d4 w = t - fl * duration;
    w = SI_DBLEND(w < zero, w + duration, w);
    const d4 clamped = SI_DBLEND(t < zero, zero, SI_DBLEND(duration < t, duration, t));
    const l4 loop = __builtin_convertvector(loop_in, l4);
    scalar |= loop & ~((w >= zero) & (w < duration));  // The exact remainder: scalar.
    const d4 ta = SI_DBLEND(loop, w, clamped);
    std::memcpy(l.time + half, &ta, sizeof ta);
    // The uniform-grid frame sample (fastSample).
    const d4 position = ta * inv_interval;
    const d4 pc = SI_DBLEND(position >= last, last, SI_DBLEND(position > zero, position, zero));
    const i4 frame = __builtin_convertvector(pc, i4);
    d4 frac = position - __builtin_convertvector(frame, d4);
    frac = SI_DBLEND(frac < zero, zero, frac);
    frac = SI_DBLEND(one < frac, one, frac);
    const f4 fraction = __builtin_convertvector(frac, f4);
    const i4 scalar_out = __builtin_convertvector(scalar, i4);
    std::memcpy(l.frame + half, &frame, sizeof frame);
    std::memcpy(l.fraction + half, &fraction, sizeof fraction);
    std::memcpy(l.scalar + half, &scalar_out, sizeof scalar_out);
    frame_half[(half - base) / 4] = frame;
    fraction_half[(half - base) / 4] = fraction;
#undef SI_LOAD4
  }
  // One clip, linear intervals (setOneClip): frames (a0, a1, a0, a1), blend (the fraction's
  // bits with mode 0 in bits 30-31, the same, weight 0, the appearance). 8 lanes at once from
  // the halves in registers, stored whole: storeRecordLanes loads them 8 at a time, and a load
  // spanning two narrower stores would wait for them to reach the cache.
  typedef uint32_t u8 __attribute__((vector_size(32)));
  u8 first, color;
  SI_LOAD(first, l.first_texel);
  SI_LOAD(color, l.color);
  const u8 frame8 =
      (u8)__builtin_shufflevector(frame_half[0], frame_half[1], 0, 1, 2, 3, 4, 5, 6, 7);
  const f8 fraction8 =
      __builtin_shufflevector(fraction_half[0], fraction_half[1], 0, 1, 2, 3, 4, 5, 6, 7);
  u8 word;
  std::memcpy(&word, &fraction8, sizeof word);
  word &= 0x3FFFFFFFu;
  const u8 a0 = first + frame8 * stride, a1 = a0 + stride;
  const u8 zero_word = {};
  std::memcpy(l.frames[0] + base, &a0, sizeof a0);
  std::memcpy(l.frames[1] + base, &a1, sizeof a1);
  std::memcpy(l.frames[2] + base, &a0, sizeof a0);
  std::memcpy(l.frames[3] + base, &a1, sizeof a1);
  std::memcpy(l.blend[0] + base, &word, sizeof word);
  std::memcpy(l.blend[1] + base, &word, sizeof word);
  std::memcpy(l.blend[2] + base, &zero_word, sizeof zero_word);
  std::memcpy(l.blend[3] + base, &color, sizeof color);
#undef SI_DBLEND
#undef SI_BLEND
#undef SI_LOAD
}

/// Stores the records of the `n` (at most 8) lanes of `l` from `base` on, lane k at out[k]:
/// rows[row][0..2] and the camera-relative translation (rx, ry, rz) as the world rows, then
/// frames[0..3] and blend[0..3]. The lanes are transposed in vector registers (four inputs of 8
/// lanes into 8 rows of 4) and each record is written as 5 rows of 16 bytes. Always inlined.
__attribute__((always_inline)) inline void storeRecordLanes(const RecordLanes& l, uint32_t base,
                                                            uint32_t n, void* const* out) {
  typedef float f8 __attribute__((vector_size(32)));
  typedef float f4 __attribute__((vector_size(16)));
  f4 rows[8][5];  // Per lane its record's five 16-byte rows.
  const auto transpose = [&](const void* a, const void* b, const void* c, const void* d, int row) {
    f8 va, vb, vc, vd;
    std::memcpy(&va, static_cast<const float*>(a) + base, sizeof va);
    std::memcpy(&vb, static_cast<const float*>(b) + base, sizeof vb);
    std::memcpy(&vc, static_cast<const float*>(c) + base, sizeof vc);
    std::memcpy(&vd, static_cast<const float*>(d) + base, sizeof vd);
    // Pairs (a0 b0 a1 b1 | a4 b4 a5 b5) ..., then quadruples (a0 b0 c0 d0 | a4 b4 c4 d4) ...
    const f8 t0 = __builtin_shufflevector(va, vb, 0, 8, 1, 9, 4, 12, 5, 13);
    const f8 t1 = __builtin_shufflevector(va, vb, 2, 10, 3, 11, 6, 14, 7, 15);
    const f8 t2 = __builtin_shufflevector(vc, vd, 0, 8, 1, 9, 4, 12, 5, 13);
    const f8 t3 = __builtin_shufflevector(vc, vd, 2, 10, 3, 11, 6, 14, 7, 15);
    const f8 u[4] = {__builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13),
                     __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15),
                     __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13),
                     __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15)};
    for (int k = 0; k < 4; ++k) {
      rows[k][row] = __builtin_shufflevector(u[k], u[k], 0, 1, 2, 3);
      rows[k + 4][row] = __builtin_shufflevector(u[k], u[k], 4, 5, 6, 7);
    }
  };
  transpose(l.rows[0][0], l.rows[0][1], l.rows[0][2], l.rx, 0);
  transpose(l.rows[1][0], l.rows[1][1], l.rows[1][2], l.ry, 1);
  transpose(l.rows[2][0], l.rows[2][1], l.rows[2][2], l.rz, 2);
  transpose(l.frames[0], l.frames[1], l.frames[2], l.frames[3], 3);
  transpose(l.blend[0], l.blend[1], l.blend[2], l.blend[3], 4);
  for (uint32_t k = 0; k < n; ++k) std::memcpy(out[k], rows[k], sizeof rows[k]);
}

}  // namespace si::detail
