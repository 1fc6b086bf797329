// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Shading of every colour path: base colour texture times factor, the instance's tint where
// the texture's alpha (the tint mask) says so, one directional light.
in vec3 v_normal;
in vec2 v_texcoord;
flat in uint v_color;
layout(binding = 1) uniform sampler2D u_base_color;
layout(location = 2) uniform vec4 u_base_factor;
layout(location = 3) uniform vec3 u_light_direction;
out vec4 o_color;
void main() {
  vec4 texel = texture(u_base_color, v_texcoord) * u_base_factor;
  vec4 tint = unpackUnorm4x8(v_color);
  // The texture's alpha is the tint mask: 1 takes the instance's colour, 0 keeps the texel.
  vec3 albedo = mix(texel.rgb, texel.rgb * tint.rgb, texel.a);
  float lambert = max(dot(normalize(v_normal), -u_light_direction), 0.0);
  o_color = vec4(albedo * (0.35 + 0.65 * lambert), 1.0);
}
