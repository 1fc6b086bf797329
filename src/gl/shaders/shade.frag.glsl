// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Shading of every colour path: the vertex's material (its layer of the base colour texture
// array times its factor), the instance's tint where the texture's alpha (the tint mask) says
// so, one directional light.
#define SI_MATERIAL_TABLE
#include "material_common.glsl"
in vec3 v_normal;
in vec2 v_texcoord;
flat in uint v_color;
flat in uint v_material;
layout(binding = 1) uniform sampler2DArray u_base_color;
layout(location = 3) uniform vec3 u_light_direction;
out vec4 o_color;
void main() {
  SiMaterial material = si_materials[v_material];
  vec4 texel = texture(u_base_color, vec3(v_texcoord, float(material.layer.x))) * material.factor;
  vec4 tint = unpackUnorm4x8(v_color);
  // The texture's alpha is the tint mask: 1 takes the instance's colour, 0 keeps the texel.
  vec3 albedo = mix(texel.rgb, texel.rgb * tint.rgb, texel.a);
  float lambert = max(dot(normalize(v_normal), -u_light_direction), 0.0);
  o_color = vec4(albedo * (0.35 + 0.65 * lambert), 1.0);
}
