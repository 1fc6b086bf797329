// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The built-in material (si::kBuiltinMaterial), a material like any other (si_surface.glsl):
// glTF 2.0 metallic-roughness (the specification's Appendix B BRDF: Lambert diffuse, GGX
// distribution, height-correlated Smith visibility, Schlick Fresnel with F0 0.04 for
// dielectrics) under the library's light set: the directional light of
// Renderer::setLightDirection with radiance 0.65 * pi (a Lambert surface facing it returns
// 0.65 of its albedo, as the library's Lambert shading before the material did) and a constant
// white ambient of 0.35, both white; the ambient's diffuse part is scaled by the surface's
// occlusion, its specular part taken as the Fresnel reflectance at normal incidence times the
// occlusion. Emissive added. The albedo is the built-in one (base colour, custom layer and tint
// under the tint mask). With motion vectors the fragment's screen motion at output 1.
layout(location = 0) out vec4 o_color;
#ifdef SI_MOTION_VECTORS
layout(location = 1) out vec2 o_motion;
#endif
const float kSiPi = 3.14159265;
void siMaterial(SiSurface s) {
  vec3 albedo = siSurfaceAlbedo(s);
  vec3 n = s.normal;
  vec3 l = -siLightDirection();
  float view_length = length(s.position);
  vec3 v = view_length > 0.0 ? -s.position / view_length : n;
  vec3 h = normalize(l + v);
  float n_l = max(dot(n, l), 0.0), n_v = max(abs(dot(n, v)), 1e-4), n_h = max(dot(n, h), 0.0);
  float v_h = max(dot(v, h), 0.0);
  float alpha = s.roughness * s.roughness;
  float a2 = max(alpha * alpha, 1e-6);
  vec3 f0 = mix(vec3(0.04), albedo, s.metallic);
  vec3 diffuse_color = albedo * (1.0 - s.metallic);
  vec3 fresnel = f0 + (1.0 - f0) * pow(1.0 - v_h, 5.0);
  float d = n_h * n_h * (a2 - 1.0) + 1.0;
  float distribution = a2 / (kSiPi * d * d);
  float visibility = 0.5 / max(n_l * sqrt(n_v * n_v * (1.0 - a2) + a2) +
                                   n_v * sqrt(n_l * n_l * (1.0 - a2) + a2), 1e-6);
  vec3 brdf = (1.0 - fresnel) * diffuse_color / kSiPi + fresnel * distribution * visibility;
  vec3 direct = brdf * (0.65 * kSiPi) * n_l;
  vec3 ambient = 0.35 * s.occlusion * (diffuse_color + f0);
  o_color = vec4(direct + ambient + s.emissive, 1.0);
#ifdef SI_MOTION_VECTORS
  o_motion = siSurfaceMotion(s);
#endif
}
