// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The material of Renderer::buildImpostor's capture (si_surface.glsl): the impostor atlas's two
// layers, which impostor.frag.glsl turns back into a surface: the base colour (clamped) and
// coverage 1, and the normal (0.5 n + 0.5) with the tint mask.
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_normal_mask;
void siMaterial(SiSurface s) {
  o_color = vec4(clamp(s.base_color.rgb, 0.0, 1.0), 1.0);
  o_normal_mask = vec4(s.normal * 0.5 + 0.5, clamp(s.base_color.a, 0.0, 1.0));
}
