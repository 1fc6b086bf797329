// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Each impostor cell's covered rectangle at every mip level of its atlas, measured on the GPU
// (the Vulkan back-end's buildImpostor, which waits for no submission; si::gl reads the atlas
// back: resources/impostor_coverage.h defines the rectangle, this computes the same one). One
// thread per texel of one level adds its extent to the cells it overlaps: the extent of any
// coverage, and of the texels at least half covered widened by a texel either way (where
// bilinear filtering can weigh them). SI_COVERAGE_RECTS: one thread per cell and level packs
// their intersection into the clip table (impostor_quad.glsl's SiImpostorClips).
#include "dispatch_index.glsl"
layout(local_size_x = 64) in;
layout(binding = 3) uniform sampler2DArray u_impostor;
// Per (cell, level) e = cell * levels + level: at 4e the minima (any coverage's left, bottom;
// the half-covered texels' left, bottom), at 4 (cells x levels) + 4e the maxima (right, top,
// alike), in level-0 texels as fixed point (256ths, plus 2^24 so that every value is positive):
// the minima filled with 0xFFFFFFFF, the maxima with 0 before the first level.
layout(std430, binding = 15) buffer SiCoverageExtents { uint si_extents[]; };
layout(std430, binding = 9) buffer SiImpostorClipWords { uint si_clip_words[]; };
layout(location = 46) uniform uvec4 u_coverage_level;  // level, its width, its height, levels
layout(location = 47) uniform uvec4 u_coverage_atlas;  // columns, rows, cell texels, clips

const float kFixed = 256.0, kOffset = 16777216.0;

#ifndef SI_COVERAGE_RECTS
uint siFixedDown(float v) { return uint(max(floor(v * kFixed) + kOffset, 0.0)); }
uint siFixedUp(float v) { return uint(max(ceil(v * kFixed) + kOffset, 0.0)); }

void main() {
  uint i = siFlatInvocation();
  uint level = u_coverage_level.x, w = u_coverage_level.y, h = u_coverage_level.z;
  if (i >= w * h) return;
  uint x = i % w, y = i / w;
  uint alpha = uint(texelFetch(u_impostor, ivec3(int(x), int(y), 0), int(level)).a * 255.0 + 0.5);
  if (alpha == 0u) return;
  uint columns = u_coverage_atlas.x, rows = u_coverage_atlas.y, cell = u_coverage_atlas.z;
  uint levels = u_coverage_level.w, entries = columns * rows * levels;
  // The texel's edges in level-0 texels, the cells it overlaps (a coarse texel may straddle two).
  vec2 scale = vec2(float(columns * cell) / float(w), float(rows * cell) / float(h));
  vec2 low = vec2(x, y) * scale, high = vec2(x + 1u, y + 1u) * scale;
  uvec2 first = min(uvec2(low / float(cell)), uvec2(columns, rows) - 1u);
  uvec2 last = min(uvec2(ceil(high / float(cell))) - 1u, uvec2(columns, rows) - 1u);
  bool half_covered = alpha >= 127u;
  vec2 reach = 0.5 * (high - low);
  for (uint cy = first.y; cy <= last.y; ++cy)
    for (uint cx = first.x; cx <= last.x; ++cx) {
      uint e = (cy * columns + cx) * levels + level;
      vec2 origin = vec2(cx, cy) * float(cell);
      vec2 lo = low - origin, hi = high - origin;
      atomicMin(si_extents[4u * e], siFixedDown(lo.x));
      atomicMin(si_extents[4u * e + 1u], siFixedDown(lo.y));
      atomicMax(si_extents[4u * (entries + e)], siFixedUp(hi.x));
      atomicMax(si_extents[4u * (entries + e) + 1u], siFixedUp(hi.y));
      if (!half_covered) continue;
      atomicMin(si_extents[4u * e + 2u], siFixedDown(lo.x - reach.x));
      atomicMin(si_extents[4u * e + 3u], siFixedDown(lo.y - reach.y));
      atomicMax(si_extents[4u * (entries + e) + 2u], siFixedUp(hi.x + reach.x));
      atomicMax(si_extents[4u * (entries + e) + 3u], siFixedUp(hi.y + reach.y));
    }
}
#else
// A fixed-point extent back in fractions of the cell.
float siFraction(uint v) { return (float(v) - kOffset) / kFixed / float(u_coverage_atlas.z); }
// packCoveredRect's rounding: outwards by one 255th more.
uint siQuantize(float f, bool up) {
  float q = up ? ceil(f * 255.0) + 1.0 : floor(f * 255.0) - 1.0;
  return uint(clamp(q, 0.0, 255.0));
}

void main() {
  uint e = siFlatInvocation();
  uint entries = u_coverage_atlas.x * u_coverage_atlas.y * u_coverage_level.w;
  if (e >= entries) return;
  uint m = 4u * e, n = 4u * (entries + e);
  uint word = 0u;  // No texel at least half covered (or none covered): an empty rectangle.
  if (si_extents[m + 2u] != 0xFFFFFFFFu) {
    // Filtering passes one half only within a texel of a half-covered texel, and only within
    // the texels of any coverage.
    float left = siFraction(max(si_extents[m], si_extents[m + 2u]));
    float bottom = siFraction(max(si_extents[m + 1u], si_extents[m + 3u]));
    float right = siFraction(min(si_extents[n], si_extents[n + 2u]));
    float top = siFraction(min(si_extents[n + 1u], si_extents[n + 3u]));
    if (right > left && top > bottom)
      word = siQuantize(left, false) | siQuantize(bottom, false) << 8 |
             siQuantize(right, true) << 16 | siQuantize(top, true) << 24;
  }
  si_clip_words[u_coverage_atlas.w * 4u + e] = word;
}
#endif
