// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// An impostor's quad (Renderer::buildImpostor): from an instance's record, the atlas cell of the
// captured view direction and frame nearest the instance's, and the quad that shows it, facing
// the viewer around the character's centre, upright along the character's own vertical axis,
// cut to the part of the cell its coverage test can pass. The instanced paths' vertex shader
// computes it per vertex (impostor.vert.glsl); the GPU-driven path once per impostor in a
// compute pass (impostor_quads.comp.glsl), its vertex shader reading it packed: the vertex
// work of 4 vertices, on the few units that run vertex shaders, was 2.4 of the 5.3 ms the
// H200 took for 1M impostors (docs/performance.md, "Impostor quads computed once").
//   location 1, u_view_projection; locations 40-45 and storage binding 9: the atlas's grid,
//   counts, elevations, cell, the camera's back direction, the viewport and the clip table
//   (ImpostorAtlas::bind).
#ifndef SI_IMPOSTOR_QUAD_GLSL
#define SI_IMPOSTOR_QUAD_GLSL
#include "si_instance_record.glsl"
// Per clip, by increasing first texel: x its first palette texel, y its baked frames, z its
// first atlas frame, w its atlas frames. Then, word by word, every cell's covered rectangle at
// every mip level (cell c's level l at word clips * 4 + c * levels + l; impostor_coverage.h).
layout(std430, binding = 9) readonly buffer SiImpostorClips { uvec4 si_impostor_clips[]; };
layout(location = 1) uniform mat4 u_view_projection;
layout(location = 40) uniform uvec4 u_impostor_grid;    // columns, rows, azimuths, elevations
// Clips, palette frame stride, views, the atlas's mip levels.
layout(location = 41) uniform uvec4 u_impostor_counts;
layout(location = 42) uniform vec4 u_impostor_elevations;  // radians, increasing
layout(location = 43) uniform vec4 u_impostor_cell;     // centre (model units), cell side
layout(location = 44) uniform vec4 u_viewer;  // the camera's back direction; w 1 orthographic
// Half the viewport's width and height in pixels, the cell's side in texels.
layout(location = 45) uniform vec3 u_impostor_texels;

// A quad: its corner (x, y in [0, 1]) is centre + ((x - 0.5) * right + (y - 0.5) * up) within
// the cell, drawn between rect.xy and rect.zw.
struct SiImpostorQuad {
  vec3 centre;  // The cell's centre, camera-relative world units.
  vec3 right;   // The cell's right side, one cell wide, world units.
  vec3 up;      // Its up side.
  vec4 rect;    // Where the coverage test can pass: left, bottom, right, top (k / 255);
                // one point (no fragment) where it passes nowhere.
  uint cell;    // The atlas cell.
  uint color;   // The record's appearance word (SiInstance.blend.w).
};

const float kPi = 3.14159265358979;
// The quad's part where the coverage test can pass, as fractions of the cell (left, bottom,
// right, top): the union of cell `cell`'s rectangles (impostor_coverage.h) at the mip levels its
// fragments can sample. Trilinear filtering at level of detail lambda reads levels
// floor(lambda) and floor(lambda) + 1 (magnified, lambda <= 0: level 0 alone). A pixel steps
// between the cell's texels over the largest and the least singular value of the quad's edges on
// screen (`right` and `up`, the cell's sides from `centre`), which bound lambda; a quarter of a
// level more each way covers the driver's approximations and perspective over the quad. A quad
// behind the eye or edge-on takes every level.
vec4 siCoveredRect(uint cell, vec3 centre, vec3 right, vec3 up) {
  uint levels = u_impostor_counts.w;
  uint lo = 0u, hi = levels - 1u;
  vec4 c = u_view_projection * vec4(centre, 1.0);
  vec4 r = u_view_projection * vec4(centre + right, 1.0);
  vec4 u = u_view_projection * vec4(centre + up, 1.0);
  if (c.w > 0.0 && r.w > 0.0 && u.w > 0.0) {
    vec2 a = (r.xy / r.w - c.xy / c.w) * u_impostor_texels.xy;
    vec2 b = (u.xy / u.w - c.xy / c.w) * u_impostor_texels.xy;
    float f = dot(a, a) + dot(b, b), det = abs(a.x * b.y - a.y * b.x);
    float root = sqrt(max(f * f - 4.0 * det * det, 0.0));
    float least = sqrt(2.0 * det * det / (f + root)), most = sqrt(0.5 * (f + root));
    if (least > 0.0) {
      float lambda_lo = log2(u_impostor_texels.z / most) - 0.25;
      float lambda_hi = log2(u_impostor_texels.z / least) + 0.25;
      lo = lambda_lo > 0.0 ? uint(min(floor(lambda_lo), float(levels - 1u))) : 0u;
      hi = lambda_hi > 0.0 ? uint(min(floor(lambda_hi) + 1.0, float(levels - 1u))) : 0u;
    }
  }
  vec4 rect = vec4(1.0, 1.0, 0.0, 0.0);  // Empty.
  for (uint level = lo; level <= hi; ++level) {
    uint word = u_impostor_counts.x * 4u + cell * levels + level;
    uint bits = si_impostor_clips[word / 4u][word % 4u];
    if (bits == 0u) continue;  // Nothing at least half covered.
    vec4 q = vec4((uvec4(bits) >> uvec4(0u, 8u, 16u, 24u)) & 0xFFu) / 255.0;
    rect = vec4(min(rect.xy, q.xy), max(rect.zw, q.zw));
  }
  return rect;
}

// The quad of the instance whose record is `inst`.
SiImpostorQuad siImpostorQuad(SiInstance inst) {
  vec4 r0 = inst.world_rows[0], r1 = inst.world_rows[1], r2 = inst.world_rows[2];
  mat3 m = transpose(mat3(r0.xyz, r1.xyz, r2.xyz));  // Model to world (rotation * scale).
  vec3 centre = m * u_impostor_cell.xyz + vec3(r0.w, r1.w, r2.w);  // Camera-relative.
  float scale = length(m[0]);
  // Towards the viewer; the character's vertical axis made perpendicular to it.
  vec3 towards = u_viewer.w > 0.5 ? u_viewer.xyz : -normalize(centre);
  vec3 up0 = normalize(m[1]);
  vec3 right = cross(up0, towards);
  // The view direction in model space: elevation and azimuth, the nearest captured of each.
  vec3 d = normalize(transpose(m) * towards);
  float elevation = asin(clamp(d.y, -1.0, 1.0));
  uint e = 0u;
  for (uint k = 1u; k < u_impostor_grid.w; ++k)
    if (abs(elevation - u_impostor_elevations[k]) < abs(elevation - u_impostor_elevations[e])) e = k;
  // The nearest azimuth step, wrapped into [0, azimuths) by mod() (a negative int % is undefined).
  float azimuths = float(u_impostor_grid.z);
  uint a = min(uint(mod(floor(atan(-d.x, d.z) * azimuths / (2.0 * kPi) + 0.5), azimuths)),
               u_impostor_grid.z - 1u);
  // Straight along the vertical axis (a top-down camera) the view has no azimuth (atan(0, 0)
  // is undefined): the middle step's cell, the billboard turned as that cell was captured (its
  // screen right is the model's (cos, 0, sin) of the step's angle: gl/view_rotation.h).
  if (dot(right, right) < 1e-8) {
    a = u_impostor_grid.z / 2u;
    float step = 2.0 * kPi * float(a) / azimuths;
    right = m * vec3(cos(step), 0.0, sin(step));
  }
  right = normalize(right);
  vec3 up = cross(towards, right);
  uint view = e * u_impostor_grid.z + a;
  // The frame: the heavier clip's texel and fraction, its clip by binary search.
  bool b = uintBitsToFloat(inst.blend.z) > 0.5;
  uint texel = b ? inst.frames.z : inst.frames.x;
  float fraction = uintBitsToFloat((b ? inst.blend.y : inst.blend.x) & 0x3FFFFFFFu);
  int lo = 0, hi = int(u_impostor_counts.x) - 1;
  while (lo < hi) {
    int mid = (lo + hi + 1) / 2;
    if (si_impostor_clips[mid].x <= texel) lo = mid;
    else hi = mid - 1;
  }
  uvec4 clip = si_impostor_clips[lo];
  float frame = texel >= clip.x ? float((texel - clip.x) / u_impostor_counts.y) + fraction : 0.0;
  uint k = clip.w > 1u && clip.y > 1u
               ? min(uint(frame * float(clip.w - 1u) / float(clip.y - 1u) + 0.5), clip.w - 1u)
               : 0u;
  SiImpostorQuad q;
  q.cell = (clip.z + k) * u_impostor_counts.z + view;
  float side = u_impostor_cell.w * scale;
  q.centre = centre;
  q.right = right * side;
  q.up = up * side;
  q.rect = siCoveredRect(q.cell, centre, q.right, q.up);
  if (q.rect.x > q.rect.z) q.rect = vec4(0.5);
  q.color = inst.blend.w;
  return q;
}

// The quad in 3 words of 16 bytes (the rectangle as 4 bytes: it is k / 255, or 0.5 for one
// point), and back.
void siPackImpostorQuad(SiImpostorQuad q, out uvec4 w0, out uvec4 w1, out uvec4 w2) {
  w0 = uvec4(floatBitsToUint(q.centre), q.cell);
  w1 = uvec4(floatBitsToUint(q.right), packUnorm4x8(q.rect));
  w2 = uvec4(floatBitsToUint(q.up), q.color);
}
SiImpostorQuad siUnpackImpostorQuad(uvec4 w0, uvec4 w1, uvec4 w2) {
  SiImpostorQuad q;
  q.centre = uintBitsToFloat(w0.xyz);
  q.cell = w0.w;
  q.right = uintBitsToFloat(w1.xyz);
  q.rect = unpackUnorm4x8(w1.w);
  q.up = uintBitsToFloat(w2.xyz);
  q.color = w2.w;
  return q;
}
#endif
