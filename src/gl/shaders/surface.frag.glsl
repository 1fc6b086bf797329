// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The fragment stage of every mesh colour path: the surface (si_surface.glsl) from the vertex
// shader's outputs and the character's materials (the vertex's entry of the material table:
// its textures sampled, its factors applied, the normal map through the skinned tangent frame,
// the alpha mask's discard), handed to the material (si::MaterialDesc, compiled
// after this file; the built-in one is builtin_material.glsl). SI_DEPTH_ONLY: a depth-only
// pass of a material that discards (MaterialDesc::depth_discard).
#define SI_MATERIAL_TABLE
#include "material_common.glsl"
#include "surface_common.glsl"
SI_VARYING_LAYOUT(0) in vec3 v_position;
SI_VARYING_LAYOUT(1) in vec3 v_normal;
// w 0: the mesh has no tangents (or the path does not carry them).
SI_VARYING_LAYOUT(2) in vec4 v_tangent;
SI_VARYING_LAYOUT(3) in vec2 v_texcoord;
#ifdef SI_VERTEX_WORDS  // The variant for meshes with texture coordinates 1 or colours.
SI_VARYING_LAYOUT(9) in vec2 v_texcoord1;     // Read where the mesh has it (material.layer.w & 1).
SI_VARYING_LAYOUT(10) in vec4 v_vertex_color;  // Read where the mesh has it (material.layer.w & 2).
#endif
SI_VARYING_LAYOUT(4) flat in uint v_color;
SI_VARYING_LAYOUT(5) flat in uint v_material;
SI_VARYING_LAYOUT(6) flat in uint v_lod;
SI_BINDING_LAYOUT(1) uniform sampler2DArray u_base_color;     // Colour layers (sRGB).
SI_BINDING_LAYOUT(4) uniform sampler2DArray u_material_data;  // Data layers (linear).
void main() {
  SiSurface s = siEmptySurface();
  SiMaterial material = si_materials[v_material];
  uvec4 layer = material.layer;  // Flat: every branch on it is uniform within a primitive.
  vec4 base = texture(u_base_color, vec3(v_texcoord, float(layer.x & 0xFFFFu))) * material.factor;
#ifdef SI_VERTEX_WORDS
  if ((layer.w & 2u) != 0u) {  // glTF: COLOR_0 multiplies the base colour.
    s.color = v_vertex_color;
    base *= v_vertex_color;
  }
  if ((layer.w & 1u) != 0u) s.uv1 = v_texcoord1;
#endif
  if (material.emissive.w >= 0.0) {  // Alpha-masked: alpha is coverage, the tint everywhere.
    if (base.a < material.emissive.w) discard;
    base.a = 1.0;
  }
  s.position = v_position;
  vec3 n = normalize(v_normal);
  if ((layer.z & 0x10000u) != 0u && !gl_FrontFacing) n = -n;  // Double-sided: its back face.
  s.vertex_normal = n;
  s.normal = n;
  if (v_tangent.w != 0.0) {
    vec3 t = normalize(v_tangent.xyz - n * dot(n, v_tangent.xyz));
    s.tangent = vec4(t, v_tangent.w < 0.0 ? -1.0 : 1.0);
  }
  s.uv0 = v_texcoord;
  s.material = v_material;
  s.base_color = base;
  s.metallic = material.pbr.x;
  s.roughness = material.pbr.y;
  if ((layer.y >> 16) != 0xFFFFu) {
    vec4 mr = texture(u_material_data, vec3(v_texcoord, float(layer.y >> 16)));
    s.metallic *= mr.b;
    s.roughness *= mr.g;
  }
  if ((layer.y & 0xFFFFu) != 0xFFFFu) {  // Sampled under the flat test alone (derivatives).
    vec3 m = texture(u_material_data, vec3(v_texcoord, float(layer.y & 0xFFFFu))).xyz * 2.0 - 1.0;
    m.xy *= material.pbr.z;
    vec3 b = s.tangent.w * cross(n, s.tangent.xyz);
    if (s.tangent.w != 0.0) s.normal = normalize(m.x * s.tangent.xyz + m.y * b + m.z * n);
  }
  if ((layer.z & 0xFFFFu) != 0xFFFFu)
    s.occlusion = 1.0 + material.pbr.w *
                            (texture(u_material_data, vec3(v_texcoord, float(layer.z & 0xFFFFu))).r - 1.0);
  s.emissive = material.emissive.rgb;
  if ((layer.x >> 16) != 0xFFFFu)
    s.emissive *= texture(u_base_color, vec3(v_texcoord, float(layer.x >> 16))).rgb;
  s.tint = siUnpackUnorm4x8(v_color).rgb;
  s.custom_layer = siCustomLayer(v_color);
  s.lod = v_lod;
  siMaterial(s);
}
