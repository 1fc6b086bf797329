// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The fragment stage of every mesh colour path: the surface (si_surface.glsl) from the vertex
// shader's outputs and the character's materials (the vertex's entry of the material table:
// its base colour layer times its factor), handed to the material (si::MaterialDesc, compiled
// after this file; the built-in one is builtin_material.glsl). SI_DEPTH_ONLY: a depth-only
// pass of a material that discards (MaterialDesc::depth_discard).
#define SI_MATERIAL_TABLE
#include "material_common.glsl"
#include "surface_common.glsl"
in vec3 v_position;
in vec3 v_normal;
in vec2 v_texcoord;
flat in uint v_color;
flat in uint v_material;
flat in uint v_lod;
SI_BINDING_LAYOUT(1) uniform sampler2DArray u_base_color;
void main() {
  SiSurface s = siEmptySurface();
  SiMaterial material = si_materials[v_material];
  s.position = v_position;
  s.normal = normalize(v_normal);
  s.uv0 = v_texcoord;
  s.material = v_material;
  s.base_color = texture(u_base_color, vec3(v_texcoord, float(material.layer.x))) * material.factor;
  s.tint = siUnpackUnorm4x8(v_color).rgb;
  s.custom_layer = siCustomLayer(v_color);
  s.lod = v_lod;
  siMaterial(s);
}
