// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Animated impostors (Renderer::buildImpostor): one quad per instance at the crowd's impostor
// level, a triangle strip of 4 vertices. The instance's record gives its world transform, its
// clip and frame (the heavier clip of a crossfade) and its tint; the quad faces the viewer
// around the character's centre, upright along the character's own vertical axis, and shows
// the atlas cell of the captured view direction and frame nearest the instance's.
// SI_GPU_DRIVEN: the record through a bucket entry (a_entry), from storage buffers.
// SI_DEPTH_ONLY: the atlas coordinate alone (the fragment stage tests coverage only).
// SI_INSTANCE_HANDLE: also the instance's handle (instance_handle.glsl).
#include "si_instance_record.glsl"
#include "instance_handle.glsl"
#ifdef SI_GPU_DRIVEN
layout(location = 5) in uint a_entry;
layout(std430, binding = 4) readonly buffer SiRecords { SiInstance si_records[]; };
layout(std430, binding = 5) readonly buffer SiEntries { uint si_entries[]; };
#ifdef SI_INSTANCE_HANDLE  // The cull pass's visible list: w the handle (cull_common.glsl).
layout(std430, binding = 6) readonly buffer SiVisible { uvec4 si_visible[]; };
#endif
#else
layout(std140, binding = 0) uniform SiInstances { SiInstance si_instances[SI_MAX_INSTANCES]; };
#endif
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
uniform uint u_lod;  // The crowd's impostor level (SiSurface.lod).
out vec2 v_uv;
#ifndef SI_DEPTH_ONLY
out vec3 v_position;
flat out uint v_color;
flat out uint v_lod;
// The quad's frame in world axes: right, up, towards the viewer (the atlas normal's axes).
flat out vec3 v_right;
flat out vec3 v_up;
flat out vec3 v_towards;
#endif
const float kPi = 3.14159265358979;
// The quad's part where the coverage test can pass, as fractions of the cell (left, bottom,
// right, top): the union of cell `cell`'s rectangles (impostor_coverage.h) at the mip levels its
// fragments can sample. Trilinear filtering at level of detail lambda reads levels
// floor(lambda) and floor(lambda) + 1 (magnified, lambda <= 0: level 0 alone). A pixel steps
// between the cell's texels over the largest and the least singular value of the quad's edges on
// screen (`right` and `up`, the cell's sides from `centre`), which bound lambda; a quarter of a
// level more each way covers the driver's approximations and perspective over the quad. A quad
// behind the eye or edge-on takes every level.
vec4 coveredRect(uint cell, vec3 centre, vec3 right, vec3 up) {
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
void main() {
#ifdef SI_GPU_DRIVEN
  SiInstance inst = si_records[si_entries[a_entry]];
#ifdef SI_INSTANCE_HANDLE
  v_instance_handle = si_visible[si_entries[a_entry]].w;
#endif
#else
  SiInstance inst = si_instances[gl_InstanceID];
#ifdef SI_INSTANCE_HANDLE
  v_instance_handle = siSlotHandle(uint(gl_InstanceID));
#endif
#endif
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
  uint cell = (clip.z + k) * u_impostor_counts.z + view;
  // The quad: where the coverage test can pass (nowhere: a point, no fragment).
  float side = u_impostor_cell.w * scale;
  vec4 rect = coveredRect(cell, centre, right * side, up * side);
  if (rect.x > rect.z) rect = vec4(0.5);
  vec2 corner = mix(rect.xy, rect.zw, vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)));
  v_uv = (vec2(float(cell % u_impostor_grid.x), float(cell / u_impostor_grid.x)) + corner) /
         vec2(u_impostor_grid.xy);
  vec3 world = centre + ((corner.x - 0.5) * right + (corner.y - 0.5) * up) * side;
#ifndef SI_DEPTH_ONLY
  v_position = world;
  v_color = inst.blend.w;
  v_lod = u_lod;
  v_right = right;
  v_up = up;
  v_towards = towards;
#endif
  gl_Position = u_view_projection * vec4(world, 1.0);
}
