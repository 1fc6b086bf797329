// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Animated impostors: the atlas cell's texel (layer 0: base colour and coverage; layer 1: the
// normal in the cell's frame, 0.5 n + 0.5, and the tint mask; both multiplied by the coverage,
// so filtering does not darken the edges), tinted and lit as shade.frag.glsl shades the mesh.
// Texels less than half covered are discarded. SI_DEPTH_ONLY: the coverage test alone.
layout(binding = 3) uniform sampler2DArray u_impostor;
in vec2 v_uv;
flat in uint v_color;
flat in vec3 v_light;
#ifndef SI_DEPTH_ONLY
layout(location = 0) out vec4 o_color;
#endif
void main() {
  vec4 base = texture(u_impostor, vec3(v_uv, 0.0));
  if (base.a < 0.5) discard;
#ifndef SI_DEPTH_ONLY
  vec4 extra = texture(u_impostor, vec3(v_uv, 1.0)) / base.a;
  vec3 texel = base.rgb / base.a;
  vec3 normal = extra.rgb * 2.0 - 1.0;
  vec3 albedo = mix(texel, texel * unpackUnorm4x8(v_color).rgb, clamp(extra.a, 0.0, 1.0));
  float lambert = max(dot(normalize(normal), -v_light), 0.0);
  o_color = vec4(albedo * (0.35 + 0.65 * lambert), 1.0);
#endif
}
