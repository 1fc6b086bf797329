// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Animated impostors: the atlas cell's texel (layer 0: base colour and coverage; layer 1: the
// normal in the cell's frame, 0.5 n + 0.5, and the tint mask; layer 2: metallic, roughness,
// occlusion and the material's code; all multiplied by the coverage, so filtering does not
// darken the edges) as a surface (si_surface.glsl: the normal turned into world axes by the
// quad's frame), handed to the material as a mesh's fragment is. Texels less than half covered
// are discarded. SI_DEPTH_ONLY: the coverage test alone.
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
  vec3 surface = clamp(texture(u_impostor, vec3(v_uv, 2.0)).rgb / base.a, 0.0, 1.0);
  s.metallic = surface.r;
  s.roughness = surface.g;
  s.occlusion = surface.b;
  // The material: the largest code of the 2 x 2 full-resolution texels around the coordinate
  // (codes are not averaged); where all four are empty (a minified edge), the filtered code.
  vec4 codes = textureGather(u_impostor, vec3(v_uv, 2.0), 3);
  float code = max(max(codes.x, codes.y), max(codes.z, codes.w));
  if (code == 0.0) code = texture(u_impostor, vec3(v_uv, 2.0)).a / base.a;
  uint index = uint(code * 255.0 + 0.5);
  s.material = index == 0u ? SI_NO_MATERIAL : index - 1u;
  s.tint = siUnpackUnorm4x8(v_color).rgb;
  s.lod = v_lod;
  s.impostor = true;
  siMaterial(s);
#endif
}
