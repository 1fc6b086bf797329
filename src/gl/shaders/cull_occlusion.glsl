// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling's occlusion test against the depth pyramid (hiz.comp.glsl): an instance is
// occluded when the nearest depth of its clip's bounding box (rotated and scaled with it) lies
// behind the farthest depth the pyramid holds over the box's screen rectangle. Conservative: the
// baked box contains the skinned mesh at every frame and between frames, the rectangle and the
// nearest depth are taken over the box's corners (a convex shape in front of the camera
// projects into the hull of its corners), the pyramid keeps the farthest depth; anything
// crossing the near plane is visible. (siRotate comes from cull.comp.glsl.) Depth as the draws
// write it: the camera's clip depth (si::DepthConvention: -w..w, 0..w, or reversed with the near
// plane at w) mapped to window depth by the host's depth range; the pyramid holds the farthest
// depth, the largest or, where depth shrinks with distance, the smallest.
#ifndef SI_CULL_OCCLUSION_GLSL
#define SI_CULL_OCCLUSION_GLSL
layout(location = 21) uniform mat4 u_view_proj;  // camera-relative world to clip
layout(location = 22) uniform ivec3 u_hiz_size;  // level 0 width, height; levels
layout(binding = 1) uniform sampler2D u_hiz;
// x: si::DepthConvention (0 -w..w, 1 0..w, 2 reversed 0..w); y: 1 when window depth grows with
// distance (the pyramid keeps maxima), else 0.
layout(location = 40) uniform ivec2 u_depth_mode;
layout(location = 41) uniform vec2 u_depth_range;  // glDepthRange's near and far

vec3 siRotate(vec4 q, vec3 v);

// `rel`: the instance's camera-relative position; `q`, `s`: its rotation and scale.
bool siOccluded(vec3 rel, vec4 q, float s, vec3 box_min, vec3 box_max) {
  vec2 lo = vec2(1.0), hi = vec2(-1.0);
  bool far_is_max = u_depth_mode.y != 0;
  float nearest = far_is_max ? 1.0 : 0.0;
  for (int k = 0; k < 8; ++k) {
    vec3 local = vec3((k & 1) != 0 ? box_max.x : box_min.x, (k & 2) != 0 ? box_max.y : box_min.y,
                      (k & 4) != 0 ? box_max.z : box_min.z);
    vec3 corner = rel + siRotate(q, local * s);
    vec4 c = u_view_proj * vec4(corner, 1.0);
    if (!(c.w > 0.0)) return false;  // Behind the eye: visible.
    vec3 ndc = c.xyz / c.w;
    // Nearer than the near plane: visible.
    if (u_depth_mode.x == 0 ? !(ndc.z > -1.0) : u_depth_mode.x == 1 ? !(ndc.z > 0.0)
                                                                     : !(ndc.z < 1.0))
      return false;
    lo = min(lo, ndc.xy);
    hi = max(hi, ndc.xy);
    float z01 = u_depth_mode.x == 0 ? ndc.z * 0.5 + 0.5 : ndc.z;
    float window = u_depth_range.x + (u_depth_range.y - u_depth_range.x) * z01;
    nearest = far_is_max ? min(nearest, window) : max(nearest, window);
  }
  if (any(greaterThan(lo, vec2(1.0))) || any(lessThan(hi, vec2(-1.0)))) return false;
  ivec2 size = u_hiz_size.xy;
  ivec2 p0 = clamp(ivec2(floor((clamp(lo, -1.0, 1.0) * 0.5 + 0.5) * vec2(size))), ivec2(0), size - 1);
  ivec2 p1 = clamp(ivec2(floor((clamp(hi, -1.0, 1.0) * 0.5 + 0.5) * vec2(size))), ivec2(0), size - 1);
  int level = 0;
  while (level + 1 < u_hiz_size.z &&
         ((p1.x >> level) - (p0.x >> level) > 1 || (p1.y >> level) - (p0.y >> level) > 1))
    ++level;
  ivec2 a = p0 >> level, b = p1 >> level;
  float farthest = far_is_max ? 0.0 : 1.0;
  for (int y = a.y; y <= b.y; ++y)
    for (int x = a.x; x <= b.x; ++x) {
      float d = texelFetch(u_hiz, ivec2(x, y), level).r;
      farthest = far_is_max ? max(farthest, d) : min(farthest, d);
    }
  return far_is_max ? nearest > farthest : nearest < farthest;
}
#endif
