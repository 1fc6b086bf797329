// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// Shading of every colour path: the vertex's material (its layer of the base colour texture
// array times its factor), the instance's tint where the texture's alpha (the tint mask) says
// so, there over the instance's layer of the application's custom texture array when it selects
// one, and one directional light. SI_MOTION_VECTORS: also the fragment's screen motion since the
// previous frame at output 1 (motion_output.glsl). SI_IMPOSTOR_CAPTURE: the impostor atlas's two
// layers instead (impostor.frag.glsl reads them): the unlit texel and coverage 1, and the
// normal (0.5 n + 0.5) with the tint mask.
#define SI_MATERIAL_TABLE
#include "material_common.glsl"
in vec3 v_normal;
in vec2 v_texcoord;
flat in uint v_color;
flat in uint v_material;
SI_BINDING_LAYOUT(1) uniform sampler2DArray u_base_color;
// The application's custom texture array (Renderer::setCustomTextureArray) and its layer count
// (0: none set; every select is then ignored).
SI_BINDING_LAYOUT(2) uniform sampler2DArray u_custom;
uniform uint u_custom_layers;
SI_LOCATION_LAYOUT(3) uniform vec3 u_light_direction;
layout(location = 0) out vec4 o_color;
#ifdef SI_IMPOSTOR_CAPTURE
layout(location = 1) out vec4 o_normal_mask;
#endif
#ifdef SI_MOTION_VECTORS
#include "motion_output.glsl"
#endif
void main() {
  SiMaterial material = si_materials[v_material];
  vec4 texel = texture(u_base_color, vec3(v_texcoord, float(material.layer.x))) * material.factor;
#ifdef SI_IMPOSTOR_CAPTURE
  o_color = vec4(clamp(texel.rgb, 0.0, 1.0), 1.0);
  o_normal_mask = vec4(normalize(v_normal) * 0.5 + 0.5, clamp(texel.a, 0.0, 1.0));
  return;
#endif
  vec3 tint = siUnpackUnorm4x8(v_color).rgb;
  // The instance's custom layer (the appearance word's high byte: 0 none, k layer k - 1; a
  // select past the array's layers is ignored), over the base texel by its own alpha.
  vec3 tinted = texel.rgb;
  uint select = v_color >> 24u;
  if (u_custom_layers > 0u) {  // Uniform: sampled outside any divergent branch.
    vec4 custom = texture(u_custom, vec3(v_texcoord, float(clamp(select, 1u, u_custom_layers) - 1u)));
    if (select != 0u && select <= u_custom_layers) tinted = mix(texel.rgb, custom.rgb, custom.a);
  }
  // The texture's alpha is the tint mask: 1 takes the instance's colour, 0 keeps the texel.
  vec3 albedo = mix(texel.rgb, tinted * tint, texel.a);
  float lambert = max(dot(normalize(v_normal), -u_light_direction), 0.0);
  o_color = vec4(albedo * (0.35 + 0.65 * lambert), 1.0);
#ifdef SI_MOTION_VECTORS
  siWriteMotion();
#endif
}
