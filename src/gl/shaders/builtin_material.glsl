// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The built-in material (si::kBuiltinMaterial), a material like any other (si_surface.glsl):
// the built-in albedo (base colour, the custom layer and the tint under the tint mask) lit by
// one directional light, Lambert over a constant ambient, at output 0; with motion vectors the
// fragment's screen motion at output 1.
layout(location = 0) out vec4 o_color;
#ifdef SI_MOTION_VECTORS
layout(location = 1) out vec2 o_motion;
#endif
void siMaterial(SiSurface s) {
  vec3 albedo = siSurfaceAlbedo(s);
  float lambert = max(dot(s.normal, -siLightDirection()), 0.0);
  o_color = vec4(albedo * (0.35 + 0.65 * lambert), 1.0);
#ifdef SI_MOTION_VECTORS
  o_motion = siSurfaceMotion(s);
#endif
}
