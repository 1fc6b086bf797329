// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// What every fragment stage that calls a material (si_surface.glsl) shares: the application's
// custom texture array and its layer count (Renderer::setCustomTextureArray; 0: none set, every
// select is then ignored), the light, the motion inputs, and the library's functions
// si_surface.glsl declares.
#ifndef SI_SURFACE_COMMON_GLSL
#define SI_SURFACE_COMMON_GLSL
#include "si_profile.glsl"
#include "si_surface.glsl"
SI_BINDING_LAYOUT(2) uniform sampler2DArray u_custom;
uniform uint u_custom_layers;
SI_LOCATION_LAYOUT(3) uniform vec3 u_light_direction;
#ifdef SI_MOTION_VECTORS
SI_VARYING_LAYOUT(7) in vec4 v_motion_current;
SI_VARYING_LAYOUT(8) in vec4 v_motion_previous;
#endif
#ifdef SI_INSTANCE_HANDLE
SI_VARYING_LAYOUT(11) flat in uint v_instance_handle;  // The vertex stage's instance_handle.glsl.
#endif

vec3 siLightDirection() { return u_light_direction; }

vec3 siSurfaceAlbedo(SiSurface s) {
  // The instance's custom layer over the base texel by its own alpha.
  vec3 tinted = s.base_color.rgb;
  if (u_custom_layers > 0u) {  // Uniform: sampled outside any divergent branch.
    vec4 custom = texture(u_custom, vec3(s.uv0, float(max(s.custom_layer, 0))));
    if (s.custom_layer >= 0) tinted = mix(s.base_color.rgb, custom.rgb, custom.a);
  }
  // The texture's alpha is the tint mask: 1 takes the instance's colour, 0 keeps the texel.
  return mix(s.base_color.rgb, tinted * s.tint, s.base_color.a);
}

// The custom layer an appearance word selects (its high byte: 0 none, k layer k - 1); -1 for
// none, or a select past the array's layers (or with no array set).
int siCustomLayer(uint appearance) {
  uint select = appearance >> 24u;
  return select != 0u && select <= u_custom_layers ? int(select) - 1 : -1;
}

vec2 siSurfaceMotion(SiSurface s) {
  return s.previous_clip_position.w > 0.0 && s.clip_position.w > 0.0
             ? 0.5 * (s.clip_position.xy / s.clip_position.w -
                      s.previous_clip_position.xy / s.previous_clip_position.w)
             : vec2(0.0);
}

// The fields every surface starts from: the motion and the instance handle where the program
// has them.
SiSurface siEmptySurface() {
  SiSurface s;
  s.position = vec3(0.0);
  s.normal = vec3(0.0, 0.0, 1.0);
  s.vertex_normal = s.normal;
  s.tangent = vec4(0.0);
  s.metallic = 0.0;
  s.roughness = 1.0;
  s.occlusion = 1.0;
  s.emissive = vec3(0.0);
  s.uv0 = vec2(0.0);
  s.uv1 = vec2(0.0);
  s.color = vec4(1.0);
  s.material = SI_NO_MATERIAL;
  s.base_color = vec4(1.0);
  s.tint = vec3(1.0);
  s.custom_layer = -1;
#ifdef SI_INSTANCE_HANDLE
  s.instance = v_instance_handle;
#else
  s.instance = 0u;
#endif
  s.lod = 0u;
  s.impostor = false;
#ifdef SI_MOTION_VECTORS
  s.clip_position = v_motion_current;
  s.previous_clip_position = v_motion_previous;
#else
  s.clip_position = vec4(0.0);
  s.previous_clip_position = vec4(0.0);
#endif
  return s;
}

// Defined by the material (MaterialDesc::source), compiled after the stage's main.
void siMaterial(SiSurface surface);
#endif
