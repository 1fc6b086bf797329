// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling's occlusion test against the depth pyramid (hiz.comp.glsl): an instance is
// occluded when the nearest depth of its clip's bounding box (rotated and scaled with it) lies
// behind the farthest depth the pyramid holds over the box's screen rectangle. Conservative: the
// baked box contains the skinned mesh at every frame and between frames, the rectangle and the
// nearest depth are taken over the box's corners (a convex shape in front of the camera
// projects into the hull of its corners), the pyramid keeps the farthest depth; anything
// crossing the near plane is visible. (siRotate comes from cull.comp.glsl.) Depth as the draws write it: window depth in
// [0, 1] (glDepthRange 0..1, clip depth -1..1), less is nearer.
#ifndef SI_CULL_OCCLUSION_GLSL
#define SI_CULL_OCCLUSION_GLSL
layout(location = 21) uniform mat4 u_view_proj;  // camera-relative world to clip
layout(location = 22) uniform ivec3 u_hiz_size;  // level 0 width, height; levels
layout(binding = 1) uniform sampler2D u_hiz;

vec3 siRotate(vec4 q, vec3 v);

// `rel`: the instance's camera-relative position; `q`, `s`: its rotation and scale.
bool siOccluded(vec3 rel, vec4 q, float s, vec3 box_min, vec3 box_max) {
  vec2 lo = vec2(1.0), hi = vec2(-1.0);
  float nearest = 1.0;
  for (int k = 0; k < 8; ++k) {
    vec3 local = vec3((k & 1) != 0 ? box_max.x : box_min.x, (k & 2) != 0 ? box_max.y : box_min.y,
                      (k & 4) != 0 ? box_max.z : box_min.z);
    vec3 corner = rel + siRotate(q, local * s);
    vec4 c = u_view_proj * vec4(corner, 1.0);
    if (!(c.w > 0.0)) return false;  // Behind the eye: visible.
    vec3 ndc = c.xyz / c.w;
    if (!(ndc.z > -1.0)) return false;  // Nearer than the near plane: visible.
    lo = min(lo, ndc.xy);
    hi = max(hi, ndc.xy);
    nearest = min(nearest, ndc.z * 0.5 + 0.5);
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
  float farthest = 0.0;
  for (int y = a.y; y <= b.y; ++y)
    for (int x = a.x; x <= b.x; ++x) farthest = max(farthest, texelFetch(u_hiz, ivec2(x, y), level).r);
  return nearest > farthest;
}
#endif
