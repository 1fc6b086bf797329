// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The material of Renderer::buildImpostor's capture (si_surface.glsl): the impostor atlas's three
// layers, which impostor.frag.glsl turns back into a surface: the base colour (clamped) and
// coverage 1; the normal (0.5 n + 0.5) with the tint mask; metallic, roughness, occlusion and
// the material index's code (index + 1, at most 255, over 255; 0 where nothing was drawn).
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_normal_mask;
layout(location = 2) out vec4 o_surface;
void siMaterial(SiSurface s) {
  o_color = vec4(clamp(s.base_color.rgb, 0.0, 1.0), 1.0);
  o_normal_mask = vec4(s.normal * 0.5 + 0.5, clamp(s.base_color.a, 0.0, 1.0));
  o_surface = vec4(clamp(vec3(s.metallic, s.roughness, s.occlusion), 0.0, 1.0),
                   float(min(s.material, 254u) + 1u) / 255.0);
}
