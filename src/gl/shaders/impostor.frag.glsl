// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Animated impostors: the atlas cell's texel (layer 0: base colour and coverage; layer 1: the
// normal in the cell's frame, 0.5 n + 0.5, and the tint mask; layer 2: metallic, roughness,
// occlusion and the material's code; all multiplied by the coverage, so filtering does not
// darken the edges) as a surface (si_surface.glsl: the normal turned into world axes by the
// quad's frame), handed to the material as a mesh's fragment is. Texels less than half covered
// are discarded. SI_DEPTH_ONLY: the coverage test alone. Where the capture drew one surface value
// everywhere (one material without metallic-roughness or occlusion textures), it comes in
// u_impostor_surface and layer 2 is not read: two texture reads a fragment of four, what bounds
// 100k impostors of a few pixels (impostor_surface.h).
#define SI_IMPOSTOR
layout(binding = 3) uniform sampler2DArray u_impostor;
in vec2 v_uv;
#ifndef SI_DEPTH_ONLY
#include "surface_common.glsl"
in vec3 v_position;
flat in uint v_color;
flat in uint v_lod;
// The quad's frame in world axes: right, up and towards the viewer.
flat in vec3 v_right;
flat in vec3 v_up;
flat in vec3 v_towards;
// Layer 2's one value (impostor_surface.h): metallic, roughness, occlusion and the material's
// code (index + 1) / 255, w above 0; w 0: the layer varies, read per fragment.
layout(location = 48) uniform vec4 u_impostor_surface;
#endif
void main() {
  vec4 base = texture(u_impostor, vec3(v_uv, 0.0));
  if (base.a < 0.5) discard;
#ifndef SI_DEPTH_ONLY
  vec4 extra = texture(u_impostor, vec3(v_uv, 1.0)) / base.a;
  vec3 n = extra.rgb * 2.0 - 1.0;
  SiSurface s = siEmptySurface();
  s.position = v_position;
  s.normal = normalize(n.x * v_right + n.y * v_up + n.z * v_towards);
  s.uv0 = v_uv;
  s.base_color = vec4(base.rgb / base.a, clamp(extra.a, 0.0, 1.0));
  vec4 surface = u_impostor_surface;  // A uniform branch: the whole draw takes one side.
  if (surface.w == 0.0) {
    vec4 layer = texture(u_impostor, vec3(v_uv, 2.0));
    surface.rgb = clamp(layer.rgb / base.a, 0.0, 1.0);
    // The material: the largest code of the 2 x 2 full-resolution texels around the coordinate
    // (codes are not averaged); where all four are empty (a minified edge), the filtered code.
    vec4 codes = textureGather(u_impostor, vec3(v_uv, 2.0), 3);
    surface.w = max(max(codes.x, codes.y), max(codes.z, codes.w));
    if (surface.w == 0.0) surface.w = layer.a / base.a;
  }
  s.metallic = surface.r;
  s.roughness = surface.g;
  s.occlusion = surface.b;
  uint index = uint(surface.w * 255.0 + 0.5);
  s.material = index == 0u ? SI_NO_MATERIAL : index - 1u;
  s.tint = siUnpackUnorm4x8(v_color).rgb;
  s.lod = v_lod;
  s.impostor = true;
  siMaterial(s);
#endif
}
