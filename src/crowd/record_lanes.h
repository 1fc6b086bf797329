// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Instance records for 8 instances at once, in lane vectors (lane_vectors.h): the world rows
// (glm::mat3_cast * scale, the camera-relative translation) and clip A's time (from the crowd
// clock, looped or clamped), uniform-grid frame and fraction, lane by lane the same operations
// as frame_builder.cpp's scalarRecord, playback.h's localTime and fastSample. A time the lanes
// cannot compute (not finite, or a loop past 2^53 intervals) is marked in scalar[]; the caller
// finishes per lane what one clip on a uniform grid does not cover (a crossfade, animation
// LOD, a clip with frame times, whose frame it finds from time[]).

#include <cstdint>
#include <cstring>

#include "crowd/lane_vectors.h"

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
  // Out: the world rows, the frame index and fraction; scalar[] also marks lanes whose time
  // the lanes cannot compute.
  alignas(32) float rows[3][3][kRecordBlock];  // rows[row][column]: rotation * scale.
  alignas(32) int32_t frame[kRecordBlock];
  alignas(32) float fraction[kRecordBlock];
  alignas(64) double time[kRecordBlock];  // The clip-local time (localTime) of each lane.
};

inline namespace SI_LANES_NAMESPACE {  // lane_vectors.h: one set of symbols per kind of lanes.

/// Computes the outputs of the 8 lanes of `l` from `base` on at crowd clock `clock`. Always
/// inlined: the vector types never cross a call.
SI_LANES_INLINE void computeRecordLanes(double clock, RecordLanes& l, uint32_t base) {
  using f8 = lanes::LaneVector<float, 8>;
#define SI_BLEND(m, a, b) (((m) & (a)) | (~(m) & (b)))
  // World rows: glm::mat3_cast(q) * s, transposed into rows.
  f8 qx, qy, qz, qw, s;
  lanes::loadLanes(base, qx, l.qx, qy, l.qy, qz, l.qz, qw, l.qw, s, l.s);
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
  using d4 = lanes::LaneVector<double, 4>;
  using l4 = lanes::LaneVector<int64_t, 4>;
  using i4 = lanes::LaneVector<int32_t, 4>;
  using f4 = lanes::LaneVector<float, 4>;
  for (uint32_t half = base; half < base + 8; half += 4) {
#define SI_DBLEND(m, a, b) \
  SI_LANES_CAST(d4, SI_BLEND((m), SI_LANES_CAST(l4, a), SI_LANES_CAST(l4, b)))
    d4 start_time, start_clock, speed, duration, inv_duration, inv_interval, last;
    lanes::loadLanes(half, start_time, l.start_time, start_clock, l.start_clock, speed, l.speed,
                     duration, l.duration, inv_duration, l.inv_duration, inv_interval,
                     l.inv_interval, last, l.last_interval);
    i4 scalar_in, loop_in;
    lanes::loadLanes(half, scalar_in, l.scalar, loop_in, l.loop);
    const d4 zero = {}, one = zero + 1.0;
    const d4 t = start_time + (clock - start_clock) * speed;
    l4 scalar = SI_LANES_CONVERT(scalar_in, l4);
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
    const l4 loop = SI_LANES_CONVERT(loop_in, l4);
    scalar |= loop & ~((w >= zero) & (w < duration));  // The exact remainder: scalar.
    const d4 ta = SI_DBLEND(loop, w, clamped);
    std::memcpy(l.time + half, &ta, sizeof ta);
    // The uniform-grid frame sample (fastSample).
    const d4 position = ta * inv_interval;
    const d4 pc = SI_DBLEND(position >= last, last, SI_DBLEND(position > zero, position, zero));
    const i4 frame = SI_LANES_CONVERT(pc, i4);
    d4 frac = position - SI_LANES_CONVERT(frame, d4);
    frac = SI_DBLEND(frac < zero, zero, frac);
    frac = SI_DBLEND(one < frac, one, frac);
    const f4 fraction = SI_LANES_CONVERT(frac, f4);
    const i4 scalar_out = SI_LANES_CONVERT(scalar, i4);
    std::memcpy(l.frame + half, &frame, sizeof frame);
    std::memcpy(l.fraction + half, &fraction, sizeof fraction);
    std::memcpy(l.scalar + half, &scalar_out, sizeof scalar_out);
  }
#undef SI_DBLEND
#undef SI_BLEND
}

}  // namespace SI_LANES_NAMESPACE
}  // namespace si::detail
