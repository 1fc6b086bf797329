// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Occlusion culling's depth pyramid (resources/depth_pyramid.cpp): with SI_HIZ_COPY, level 0
// from the depth texture (texels past the viewport hold the farthest depth there is; with
// SI_HIZ_MULTISAMPLE each texel the farthest of its samples); otherwise
// level k from level k - 1, each texel the farthest depth of the 2 x 2 texels it covers: the
// largest, or the smallest where depth shrinks with distance (reverse-Z, u_far_is_max 0).
// Level 0 has power-of-two sides, so every level halves exactly: texel x of level k covers
// texels x << k to ((x + 1) << k) - 1 of level 0, and never claims a depth nearer than any of
// them.
layout(local_size_x = 8, local_size_y = 8) in;
layout(location = 0) uniform ivec2 u_size;         // of the level written
layout(location = 1) uniform ivec2 u_source_size;  // of the depth copy, or of the level read
layout(location = 2) uniform int u_far_is_max;     // 1: depth grows with distance
float siFarther(float a, float b) { return u_far_is_max != 0 ? max(a, b) : min(a, b); }
#ifdef SI_HIZ_COPY
#ifdef SI_HIZ_MULTISAMPLE  // A multisampled depth: each pixel's farthest sample.
layout(binding = 0) uniform sampler2DMS u_depth;
layout(location = 3) uniform int u_samples;
float siDepth(ivec2 p) {
  float d = texelFetch(u_depth, p, 0).r;
  for (int k = 1; k < u_samples; ++k) d = siFarther(d, texelFetch(u_depth, p, k).r);
  return d;
}
#else
layout(binding = 0) uniform sampler2D u_depth;
float siDepth(ivec2 p) { return texelFetch(u_depth, p, 0).r; }
#endif
layout(binding = 0, r32f) writeonly uniform image2D u_out;
// Level 0's texel p holds the depth's pixel p, rows from the bottom as OpenGL's window. The
// Vulkan back-end's draws flip the viewport (so the image is OpenGL's): its depth's rows run
// from the top, and the area drawn starts at u_source_offset (vk::DrawTarget::offset).
#ifdef VULKAN
layout(location = 4) uniform ivec2 u_source_offset;
ivec2 siSourcePixel(ivec2 p) {
  return u_source_offset + ivec2(p.x, u_source_size.y - 1 - p.y);
}
#else
ivec2 siSourcePixel(ivec2 p) { return p; }
#endif
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, u_size))) return;
  bool inside = all(lessThan(p, u_source_size));
  imageStore(u_out, p, vec4(inside ? siDepth(siSourcePixel(p)) : float(u_far_is_max)));
}
#else
layout(binding = 0, r32f) readonly uniform image2D u_in;
layout(binding = 1, r32f) writeonly uniform image2D u_out;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, u_size))) return;
  ivec2 a = p * 2, b = min(a + 1, u_source_size - 1);
  float d = siFarther(siFarther(imageLoad(u_in, a).r, imageLoad(u_in, ivec2(b.x, a.y)).r),
                      siFarther(imageLoad(u_in, ivec2(a.x, b.y)).r, imageLoad(u_in, b).r));
  imageStore(u_out, p, vec4(d));
}
#endif
