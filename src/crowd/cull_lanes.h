// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// cull::select (cull_math.h) for 8 instances at once, in lane vectors (lane_vectors.h: GCC and
// Clang vector extensions, or the portable lanes elsewhere): lane by lane the same float
// operations in the same order, so every lane selects exactly what the scalar function (and the
// GPU-driven culling shader) selects. The compiler maps the 8 lanes onto one AVX register or two
// SSE ones, whichever the calling function is compiled for.

#include <cstdint>
#include <cstring>

#include "crowd/cull_math.h"
#include "crowd/lane_vectors.h"

namespace si::cull {

inline constexpr uint32_t kLanes = 8;
/// Instances gathered before the vector work: enough that the gathering stores have left the
/// store buffer when the vector loads read them (loads straight after narrow stores stall).
inline constexpr uint32_t kBlock = 64;

/// Why a lane was culled (or not).
enum LaneResult : int32_t { kLaneVisible = 0, kLaneCulledByDistance = 1, kLaneCulledByFrustum = 2 };

/// A block of instances' inputs, gathered (structure of arrays), and the outputs.
struct Lanes {
  alignas(32) float rx[kBlock], ry[kBlock], rz[kBlock];              // Camera-relative position.
  alignas(32) float qx[kBlock], qy[kBlock], qz[kBlock], qw[kBlock];  // Rotation.
  alignas(32) float s[kBlock];                                       // Scale.
  alignas(32) float ax[kBlock], ay[kBlock], az[kBlock], ar[kBlock];  // Clip A's sphere.
  alignas(32) float bx[kBlock], by[kBlock], bz[kBlock], br[kBlock];  // Clip B's (A's if none).
  alignas(32) int32_t lod[kBlock];     // In: the previous LOD; out: the new one (visible lanes).
  alignas(32) int32_t result[kBlock];  // Out: a LaneResult.
};

/// The LOD lines of `p` with the hysteresis applied, as select() computes them before scaling
/// by the instance's radius.
struct LodLines {
  float up[8] = {};    // lod_lines[l] * (1 + hysteresis): LOD l -> l + 1.
  float down[8] = {};  // lod_lines[l] * (1 - hysteresis): LOD l + 1 -> l.
};
inline LodLines lodLines(const Params& p) {
  LodLines l;
  for (uint32_t i = 0; i + 1 < p.lod_count && i < 7; ++i) {
    l.up[i] = p.lod_lines[i] * (1.0f + p.hysteresis);
    l.down[i] = p.lod_lines[i] * (1.0f - p.hysteresis);
  }
  return l;
}

inline namespace SI_LANES_NAMESPACE {  // lane_vectors.h: one set of symbols per kind of lanes.

/// 8 lanes of floats and of lane masks (true: all bits set), as the vector code below uses them.
using LaneFloats = lanes::LaneVector<float, 8>;
using LaneMasks = lanes::LaneVector<int32_t, 8>;

/// beyondFarLine() on the 8 lanes of `l` from `base` on, the same float operations in the same
/// order: `*d2` the squared distances, `*far` true in the lanes past the far line (or not
/// finite). Always inlined, as selectLanes, which starts with it.
SI_LANES_INLINE void farLineLanes(const Params& p, const Lanes& l, uint32_t base, LaneFloats* d2,
                                  LaneMasks* far) {
  LaneFloats rx, ry, rz, s;
  std::memcpy(&rx, l.rx + base, sizeof rx);
  std::memcpy(&ry, l.ry + base, sizeof ry);
  std::memcpy(&rz, l.rz + base, sizeof rz);
  std::memcpy(&s, l.s + base, sizeof s);
  *d2 = (rx * rx + ry * ry) + rz * rz;
  *far = ~(*d2 <= kMaxSquaredDistance);  // Not finite: culled, far line or not.
  if (p.max_distance_radii >= 0.0f) {
    const LaneFloats far_line = p.max_distance_radii * (p.radius * s);
    *far |= *d2 > far_line * far_line;
  }
}

/// Whether any of the 8 lanes of `l` from `base` on lies nearer than the far line.
SI_LANES_INLINE bool anyNearLane(const Params& p, const Lanes& l, uint32_t base) {
  LaneFloats d2;
  LaneMasks far;
  farLineLanes(p, l, base, &d2, &far);
  bool any = false;
  for (uint32_t k = 0; k < kLanes; ++k) any |= far[k] == 0;
  return any;
}

/// select() on the 8 lanes of `l` from `base` on; without `fades` (no lane crossfades: clip B's
/// sphere is clip A's in every lane) one sphere is tested, which selects the same. Always
/// inlined: the vector types never cross a call.
SI_LANES_INLINE void selectLanes(const Params& p, const LodLines& lines, Lanes& l, uint32_t base,
                                 bool fades = true) {
  using f8 = LaneFloats;
  using i8 = LaneMasks;
#define SI_BLEND(m, a, b) (((m) & (a)) | (~(m) & (b)))
  f8 rx, ry, rz, qx, qy, qz, qw, s;
  lanes::loadLanes(base, rx, l.rx, ry, l.ry, rz, l.rz, qx, l.qx, qy, l.qy, qz, l.qz, qw, l.qw, s,
                   l.s);
  const f8 radius = p.radius * s;
  f8 d2;
  i8 by_distance;
  farLineLanes(p, l, base, &d2, &by_distance);
  // The sphere centre rel + rotate(q, c * s), as cull::rotate computes it.
  const auto center = [&](const float* cx, const float* cy, const float* cz, f8* ox, f8* oy,
                          f8* oz) {
    f8 vx, vy, vz;
    lanes::loadLanes(base, vx, cx, vy, cy, vz, cz);
    vx = vx * s;
    vy = vy * s;
    vz = vz * s;
    const f8 uvx = qy * vz - vy * qz, uvy = qz * vx - vz * qx, uvz = qx * vy - vx * qy;
    const f8 uuvx = qy * uvz - uvy * qz, uuvy = qz * uvx - uvz * qx, uuvz = qx * uvy - uvx * qy;
    *ox = rx + (vx + ((uvx * qw) + uuvx) * 2.0f);
    *oy = ry + (vy + ((uvy * qw) + uuvy) * 2.0f);
    *oz = rz + (vz + ((uvz * qw) + uuvz) * 2.0f);
  };
  f8 cax, cay, caz, ar;
  center(l.ax, l.ay, l.az, &cax, &cay, &caz);
  lanes::loadLanes(base, ar, l.ar);
  const f8 ra = ar * s;
  i8 inside = ~i8{};
  if (!fades) {  // Clip B's sphere is clip A's in every lane: one test a plane.
    for (const glm::vec4& plane : p.planes)
      inside &= ((plane.x * cax + plane.y * cay) + plane.z * caz) + plane.w >= -ra;
  } else {
    f8 cbx, cby, cbz, br;
    center(l.bx, l.by, l.bz, &cbx, &cby, &cbz);
    lanes::loadLanes(base, br, l.br);
    const f8 rb = br * s;
    for (const glm::vec4& plane : p.planes) {
      const i8 a_in = ((plane.x * cax + plane.y * cay) + plane.z * caz) + plane.w >= -ra;
      const i8 b_in = ((plane.x * cbx + plane.y * cby) + plane.z * cbz) + plane.w >= -rb;
      inside &= a_in | b_in;
    }
  }
  // LOD with hysteresis: up while past the next line, then down while inside the previous one.
  i8 lod;
  lanes::loadLanes(base, lod, l.lod);
  const int32_t top = int32_t(p.lod_count) - 1;
  lod = SI_BLEND(lod < (i8{} + top), lod, i8{} + top);
  i8 moving = ~i8{};
  for (int32_t step = 0; step < top; ++step) {
    f8 up = {};
    for (int32_t k = 0; k < top; ++k)
      up = SI_LANES_CAST(f8, SI_BLEND(lod == (i8{} + k), SI_LANES_CAST(i8, f8{} + lines.up[k]),
                                      SI_LANES_CAST(i8, up)));
    const f8 line = up * radius;
    moving &= (lod < (i8{} + top)) & (d2 > line * line);
    lod -= moving;  // True lanes are -1.
  }
  moving = ~i8{};
  for (int32_t step = 0; step < top; ++step) {
    f8 down = {};
    for (int32_t k = 0; k < top; ++k)
      down = SI_LANES_CAST(
          f8, SI_BLEND(lod == (i8{} + (k + 1)), SI_LANES_CAST(i8, f8{} + lines.down[k]),
                       SI_LANES_CAST(i8, down)));
    const f8 line = down * radius;
    moving &= (lod > i8{}) & (d2 < line * line);
    lod += moving;
  }
  const i8 result = SI_BLEND(
      by_distance, i8{} + int32_t(kLaneCulledByDistance),
      SI_BLEND(inside, i8{} + int32_t(kLaneVisible), i8{} + int32_t(kLaneCulledByFrustum)));
  std::memcpy(l.lod + base, &lod, sizeof lod);
  std::memcpy(l.result + base, &result, sizeof result);
#undef SI_BLEND
}

}  // namespace SI_LANES_NAMESPACE
}  // namespace si::cull
